#include "core/viz/render_png.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/io/atomic_file.h"
#include "core/io/input_error.h"
#include "core/render/render_maps.h"

namespace es {

namespace {

// Written beside `path` (same extension, so imwrite picks the same format)
// and renamed over it: a crash never leaves a truncated image.
void Write(const cv::Mat& image, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension();
  const std::string tmp =
      path + ".tmp." + std::to_string(::getpid()) + extension;
  bool ok = false;
  try {
    ok = cv::imwrite(tmp, image);
  } catch (const cv::Exception& e) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write image: " + e.what());
  }
  if (!ok) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write image");
  }
  ReplaceFile(tmp, path);
}

}  // namespace

void WriteRgbPng(const RenderResult& result, const std::string& path) {
  cv::Mat image(result.height, result.width, CV_8UC3);
  for (int i = 0; i < result.height; ++i) {
    for (int j = 0; j < result.width; ++j) {
      const double* rgb = &result.rgb[3 * (i * result.width + j)];
      cv::Vec3b& px = image.at<cv::Vec3b>(i, j);
      for (int c = 0; c < 3; ++c) {  // OpenCV stores BGR
        px[2 - c] = static_cast<uint8_t>(
            std::lround(std::clamp(rgb[c], 0.0, 1.0) * 255));
      }
    }
  }
  Write(image, path);
}

void WriteDepthPng(const RenderResult& result, double scale,
                   const std::string& path) {
  const std::vector<double> depth = ExpectedDepth(result, 1e-3);
  cv::Mat image(result.height, result.width, CV_16UC1);
  for (int i = 0; i < result.height; ++i) {
    for (int j = 0; j < result.width; ++j) {
      const double v = depth[i * result.width + j] * scale;
      image.at<uint16_t>(i, j) = static_cast<uint16_t>(
          std::lround(std::clamp(v, 0.0, 65535.0)));
    }
  }
  Write(image, path);
}

}  // namespace es
