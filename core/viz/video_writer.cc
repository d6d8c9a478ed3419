#include "core/viz/video_writer.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <glog/logging.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/base/number_text.h"

namespace es {
namespace fs = std::filesystem;

namespace {

bool FfmpegAvailable() {
  return std::system("ffmpeg -version > /dev/null 2>&1") == 0;
}

// Single quotes for the shell; a quote inside is closed, escaped, reopened.
std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool EncodeWithFfmpeg(const std::string& frame_dir, double fps,
                      const std::string& mp4_path) {
  // yuv420p needs even sizes: pad by one pixel where odd.
  const std::string command =
      "ffmpeg -y -loglevel error -framerate " + ShortNumber(fps) + " -i " +
      ShellQuote(frame_dir + "/frame_%06d.png") +
      " -vf " + ShellQuote("pad=ceil(iw/2)*2:ceil(ih/2)*2") +
      " -c:v libx264 -pix_fmt yuv420p -crf 18 " + ShellQuote(mp4_path) +
      " < /dev/null";
  return std::system(command.c_str()) == 0 && fs::exists(mp4_path) &&
         fs::file_size(mp4_path) > 0;
}

bool EncodeWithOpenCv(const std::string& frame_dir, int frames, double fps,
                      cv::Size size, const std::string& mp4_path) {
  cv::VideoWriter writer(mp4_path, cv::VideoWriter::fourcc('m', 'p', '4', 'v'),
                         fps, size);
  if (!writer.isOpened()) return false;
  for (int i = 0; i < frames; ++i) {
    const cv::Mat frame =
        cv::imread(frame_dir + "/" + AnimationFrameName(i), cv::IMREAD_COLOR);
    if (frame.empty()) return false;
    writer.write(frame);
  }
  writer.release();
  return fs::exists(mp4_path) && fs::file_size(mp4_path) > 0;
}

}  // namespace

cv::Mat RgbToBgr8(const double* rgb, int width, int height) {
  cv::Mat out(height, width, CV_8UC3);
  for (int i = 0; i < height; ++i) {
    uint8_t* row = out.ptr<uint8_t>(i);
    for (int j = 0; j < width; ++j) {
      const double* p = rgb + (static_cast<size_t>(i) * width + j) * 3;
      for (int c = 0; c < 3; ++c) {
        const double v = std::isfinite(p[c]) ? p[c] : 0.0;
        row[j * 3 + 2 - c] = static_cast<uint8_t>(
            std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
      }
    }
  }
  return out;
}

std::string AnimationFrameName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06d.png", index);
  return name;
}

VideoWriter::VideoWriter(const std::string& frame_dir, double fps)
    : frame_dir_(frame_dir), fps_(fps) {
  CHECK_GT(fps, 0.0);
  std::error_code error;
  fs::create_directories(frame_dir, error);
  if (error) {
    throw InputError(frame_dir + ": cannot create directory: " +
                     error.message());
  }
  // Frames of an earlier, longer run would end up in the video.
  for (const auto& entry : fs::directory_iterator(frame_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".png") {
      fs::remove(entry.path());
    }
  }
}

void VideoWriter::Add(const cv::Mat& bgr) {
  CHECK_EQ(bgr.type(), CV_8UC3);
  if (frames_ == 0) size_ = bgr.size();
  CHECK(bgr.size() == size_) << "frames must all have the same size";
  const std::string path = frame_dir_ + "/" + AnimationFrameName(frames_);
  if (!cv::imwrite(path, bgr)) throw InputError(path + ": cannot write");
  ++frames_;
}

std::string VideoWriter::Finish(const std::string& mp4_path) {
  if (frames_ == 0) throw InputError(mp4_path + ": no frames to encode");
  // Encoded beside the target (the encoders pick the container from the
  // extension) and renamed over it: a killed encoder never leaves a
  // truncated video that a rerun would take as done.
  const std::string tmp =
      mp4_path + ".tmp." + std::to_string(::getpid()) + ".mp4";
  if (FfmpegAvailable() && EncodeWithFfmpeg(frame_dir_, fps_, tmp)) {
    ReplaceFile(tmp, mp4_path);
    return "ffmpeg";
  }
  if (EncodeWithOpenCv(frame_dir_, frames_, fps_, size_, tmp)) {
    ReplaceFile(tmp, mp4_path);
    return "opencv-mp4v";
  }
  std::error_code error;
  fs::remove(tmp, error);
  throw InputError(mp4_path + ": cannot encode video (no ffmpeg, and "
                   "OpenCV's mp4v writer failed)");
}

}  // namespace es
