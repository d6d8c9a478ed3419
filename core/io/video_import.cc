#include "core/io/video_import.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/io/frame_loading.h"
#include "core/io/image_file.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

void CheckOptions(const VideoImportOptions& options) {
  if (!(options.fps >= 0))
    throw InputError("--fps must be >= 0 (0: the video's own rate)");
  if (options.max_frames < 2)
    throw InputError("--max_frames must be >= 2, got " +
                     std::to_string(options.max_frames));
  if (options.max_width < 0)
    throw InputError("--max_width must be >= 0 (0: keep the width)");
  if (!options.masks_dir.empty() && !fs::is_directory(options.masks_dir))
    throw InputError(options.masks_dir + ": masks folder not found");
}

void CheckEmpty(const fs::path& dir) {
  if (fs::exists(dir) && !fs::is_empty(dir))
    throw InputError(dir.string() + ": already holds files; a video is "
                     "only imported into an empty folder (delete it to "
                     "redo the import)");
}

cv::Size WorkingSize(int width, int height, int max_width) {
  if (max_width <= 0 || width <= max_width) return {width, height};
  const int h = std::max(1, static_cast<int>(std::lround(
                                static_cast<double>(height) * max_width /
                                width)));
  return {max_width, h};
}

cv::Mat Resized(const cv::Mat& image, cv::Size size, int interpolation) {
  if (image.size() == size) return image;
  cv::Mat out;
  cv::resize(image, out, size, 0, 0, interpolation);
  return out;
}

// The user's mask of video frame `index`, binarized after resizing so an
// edited mask stays a mask.
cv::Mat ImportedMask(const std::string& masks_dir, int index, cv::Size size) {
  const std::string name = VideoFrameName(index);
  const std::string path = FindMaskFiles(masks_dir, {name})[0];
  cv::Mat mask8;
  ReadMask(path).convertTo(mask8, CV_8U, 255.0);
  cv::Mat out = Resized(mask8, size, cv::INTER_AREA);
  cv::threshold(out, out, 127, 255, cv::THRESH_BINARY);
  return out;
}

}  // namespace

VideoImportResult ImportVideo(const std::string& video,
                              const std::string& scene_dir,
                              const VideoImportOptions& options,
                              const std::function<void(int, int)>& progress) {
  CheckOptions(options);
  if (!fs::is_regular_file(video))
    throw InputError(video + ": video file not found");
  // FFmpeg directly: other back ends print noise on files they reject.
  cv::VideoCapture capture(video, cv::CAP_FFMPEG);
  if (!capture.isOpened())
    throw InputError(video + ": cannot open as a video (OpenCV/FFmpeg)");
  const fs::path images = fs::path(scene_dir) / "images";
  const fs::path masks = fs::path(scene_dir) / "masks";
  CheckEmpty(images);
  if (!options.masks_dir.empty()) CheckEmpty(masks);
  fs::create_directories(images);
  if (!options.masks_dir.empty()) fs::create_directories(masks);

  VideoImportResult result;
  result.video_fps = capture.get(cv::CAP_PROP_FPS);
  if (!(result.video_fps > 0 && result.video_fps < 1000))
    result.video_fps = 0;
  if (options.fps > 0 && result.video_fps > 0)
    result.step = std::max(
        1, static_cast<int>(std::lround(result.video_fps / options.fps)));
  const int counted = static_cast<int>(capture.get(cv::CAP_PROP_FRAME_COUNT));
  const int expected =
      counted > 0
          ? std::min(options.max_frames, (counted + result.step - 1) /
                                             result.step)
          : options.max_frames;

  cv::Mat frame;
  for (int index = 0; result.frames < options.max_frames; ++index) {
    if (!capture.read(frame) || frame.empty()) break;
    ++result.video_frames;
    if (index % result.step != 0) continue;
    if (frame.channels() == 1) cv::cvtColor(frame, frame, cv::COLOR_GRAY2BGR);
    const cv::Size size =
        WorkingSize(frame.cols, frame.rows, options.max_width);
    if (result.frames == 0) {
      result.width = size.width;
      result.height = size.height;
    } else if (size != cv::Size(result.width, result.height)) {
      throw InputError(video + ": frame " + std::to_string(index) +
                       " changes the frame size");
    }
    const std::string name = VideoFrameName(result.frames);
    WriteImageAtomically((images / name).string(),
                         Resized(frame, size, cv::INTER_AREA));
    if (!options.masks_dir.empty())
      WriteImageAtomically((masks / name).string(),
                           ImportedMask(options.masks_dir, index, size));
    ++result.frames;
    if (progress) progress(result.frames, std::max(expected, result.frames));
  }
  if (result.frames < 2)
    throw InputError(video + ": decoded " + std::to_string(result.frames) +
                     " frame(s); a loop needs at least 2");
  return result;
}

}  // namespace es
