#include "core/viz/render_png.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/io/image_file.h"
#include "core/render/render_maps.h"

namespace es {

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
  WriteImageAtomically(path, image);
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
  WriteImageAtomically(path, image);
}

}  // namespace es
