#include "core/raster_io.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/input_error.h"

namespace es {

Camera PinholeCameraFromColmap(const ColmapCamera& camera,
                               const ColmapImage& image,
                               const std::string& source) {
  Camera c;
  const std::vector<double>& p = camera.params;
  if (camera.model == "PINHOLE" && p.size() == 4) {
    c.fx = p[0];
    c.fy = p[1];
    c.cx = p[2];
    c.cy = p[3];
  } else if (camera.model == "SIMPLE_PINHOLE" && p.size() == 3) {
    c.fx = c.fy = p[0];
    c.cx = p[1];
    c.cy = p[2];
  } else {
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " has model " + camera.model + " with " +
                     std::to_string(p.size()) +
                     " parameters; rendering supports only PINHOLE and "
                     "SIMPLE_PINHOLE (undistort the images first)");
  }
  if (camera.width <= 0 || camera.height <= 0 || !(c.fx > 0) ||
      !(c.fy > 0)) {
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " has an invalid size or focal length");
  }
  c.width = camera.width;
  c.height = camera.height;
  c.q_cw = image.q_cw;
  c.t_cw = image.t_cw;
  c.image_name = image.name;
  c.image_id = image.id;
  return c;
}

Eigen::Vector3d ParseColor(const std::string& text, const std::string& flag) {
  std::stringstream in(text);
  std::string item;
  std::vector<double> values;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' ||
        !std::isfinite(v)) {
      throw InputError("--" + flag + "=" + text + ": '" + item +
                       "' is not a number (expected r,g,b)");
    }
    values.push_back(v);
  }
  if (values.size() != 3 || text.back() == ',') {
    throw InputError("--" + flag + "=" + text +
                     ": expected three comma-separated numbers r,g,b");
  }
  return {values[0], values[1], values[2]};
}

namespace {

void Write(const cv::Mat& image, const std::string& path) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write image: " + e.what());
  }
  if (!ok) throw InputError(path + ": cannot write image");
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
