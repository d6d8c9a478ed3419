#include "core/io/frame_loading.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>

#include <glog/logging.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool IsImageFile(const fs::path& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

bool IsVideoFile(const fs::path& path) {
  const std::string ext = LowerExtension(path);
  for (const char* video : {".mp4", ".avi", ".mov", ".mkv", ".webm", ".m4v"})
    if (ext == video) return true;
  return false;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

// The single video in images_dir, or empty if it holds image files (or no
// video).
fs::path FindVideo(const fs::path& images_dir) {
  std::error_code ec;
  if (!fs::is_directory(images_dir, ec))
    throw InputError(images_dir.string() + ": images folder not found");
  std::vector<fs::path> videos;
  for (const fs::directory_entry& entry :
       fs::directory_iterator(images_dir, ec)) {
    if (!entry.is_regular_file()) continue;
    if (IsImageFile(entry.path())) return {};
    if (IsVideoFile(entry.path())) videos.push_back(entry.path());
  }
  if (videos.size() > 1) {
    std::vector<std::string> names;
    for (const fs::path& v : videos) names.push_back(v.filename().string());
    std::sort(names.begin(), names.end());
    throw InputError(images_dir.string() + ": holds several videos (" +
                     JoinNames(names) + "); keep one");
  }
  return videos.empty() ? fs::path() : videos[0];
}

void ReadImageFiles(
    const fs::path& images_dir, const std::vector<std::string>& names,
    const std::function<void(int, const cv::Mat&, const std::string&)>& visit) {
  std::vector<std::string> missing;
  for (const std::string& name : names)
    if (!fs::is_regular_file(images_dir / name)) missing.push_back(name);
  if (!missing.empty())
    throw InputError(
        images_dir.string() + ": " + std::to_string(missing.size()) +
        " image(s) of the COLMAP model are missing: " + JoinNames(missing));
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string path = (images_dir / names[i]).string();
    const cv::Mat image =
        cv::imread(path, cv::IMREAD_COLOR | cv::IMREAD_ANYDEPTH);
    if (image.empty()) throw InputError(path + ": cannot decode image");
    visit(i, image, path);
  }
}

void ReadVideoFrames(
    const fs::path& video, const std::vector<std::string>& names,
    const std::function<void(int, const cv::Mat&, const std::string&)>& visit) {
  // Frame index -> position in names; names not of the frame form never
  // match and are reported missing.
  std::map<int, int> wanted;
  for (size_t i = 0; i < names.size(); ++i) {
    int index = -1;
    if (std::sscanf(names[i].c_str(), "frame_%d", &index) == 1 && index >= 0 &&
        names[i] == VideoFrameName(index))
      wanted[index] = i;
  }
  // FFmpeg directly: other back ends (GStreamer) print noise, and leak, on
  // files they reject.
  cv::VideoCapture capture(video.string(), cv::CAP_FFMPEG);
  if (!capture.isOpened())
    throw InputError(video.string() + ": cannot open video");
  std::vector<bool> found(names.size(), false);
  cv::Mat frame;
  for (int index = 0; !wanted.empty() && index <= wanted.rbegin()->first;
       ++index) {
    if (!capture.read(frame) || frame.empty()) break;
    const auto it = wanted.find(index);
    if (it == wanted.end()) continue;
    found[it->second] = true;
    visit(it->second, frame,
          video.string() + " frame " + std::to_string(index) + " (" +
              names[it->second] + ")");
  }
  std::vector<std::string> missing;
  for (size_t i = 0; i < names.size(); ++i)
    if (!found[i]) missing.push_back(names[i]);
  if (!missing.empty())
    throw InputError(video.string() + ": " + std::to_string(missing.size()) +
                     " frame(s) of the COLMAP model are not in the video "
                     "(frames are named " +
                     VideoFrameName(0) + ", ...): " + JoinNames(missing));
}

}  // namespace

std::string VideoFrameName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06d.png", index);
  return name;
}

void ForEachFrameImage(
    const std::string& images_dir, const std::vector<std::string>& names,
    const std::function<void(int, const cv::Mat&, const std::string&)>& visit) {
  const fs::path video = FindVideo(images_dir);
  if (video.empty()) {
    ReadImageFiles(images_dir, names, visit);
  } else {
    ReadVideoFrames(video, names, visit);
  }
}

std::vector<int> FrameTimeIndices(const std::string& images_dir,
                                  const std::vector<std::string>& names) {
  std::vector<int> times(names.size());
  const fs::path video = FindVideo(images_dir);
  if (!video.empty()) {
    for (size_t i = 0; i < names.size(); ++i) {
      int index = -1;
      if (std::sscanf(names[i].c_str(), "frame_%d", &index) != 1 ||
          index < 0 || names[i] != VideoFrameName(index))
        throw InputError(video.string() + ": '" + names[i] +
                         "' is not a frame name of a video (frames are "
                         "named " + VideoFrameName(0) + ", ...)");
      times[i] = index;
    }
    return times;
  }
  std::vector<std::string> all;
  for (const fs::directory_entry& entry :
       fs::recursive_directory_iterator(images_dir)) {
    if (entry.is_regular_file() && IsImageFile(entry.path()))
      all.push_back(fs::relative(entry.path(), images_dir).string());
  }
  std::sort(all.begin(), all.end());
  for (size_t i = 0; i < names.size(); ++i) {
    const auto it = std::lower_bound(all.begin(), all.end(), names[i]);
    if (it == all.end() || *it != names[i])
      throw InputError(images_dir + ": no image " + names[i]);
    times[i] = static_cast<int>(it - all.begin());
  }
  return times;
}

std::vector<std::string> FindMaskFiles(const std::string& masks_dir,
                                       const std::vector<std::string>& names) {
  std::vector<std::string> files, missing;
  for (const std::string& name : names) {
    const fs::path same = fs::path(masks_dir) / name;
    fs::path png = same;
    png.replace_extension(".png");
    if (fs::is_regular_file(same)) {
      files.push_back(same.string());
    } else if (fs::is_regular_file(png)) {
      files.push_back(png.string());
    } else {
      missing.push_back(name);
    }
  }
  if (!missing.empty())
    throw InputError(masks_dir + ": no mask for " +
                     std::to_string(missing.size()) +
                     " frame(s): " + JoinNames(missing));
  return files;
}

cv::Mat ReadMask(const std::string& path) {
  const cv::Mat raw =
      cv::imread(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  if (raw.empty()) throw InputError(path + ": cannot decode mask");
  if (raw.depth() != CV_8U && raw.depth() != CV_16U)
    throw InputError(path + ": mask must have 8 or 16 bits per pixel");
  cv::Mat mask;
  raw.convertTo(mask, CV_32F, raw.depth() == CV_8U ? 1.0 / 255 : 1.0 / 65535);
  return mask;
}

cv::Mat ToRgbFloat(const cv::Mat& bgr) {
  CHECK_EQ(bgr.channels(), 3);
  CHECK(bgr.depth() == CV_8U || bgr.depth() == CV_16U);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::Mat out;
  rgb.convertTo(out, CV_32F, bgr.depth() == CV_16U ? 1.0 / 65535 : 1.0 / 255);
  return out;
}

}  // namespace es
