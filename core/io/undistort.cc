#include "core/io/undistort.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"

namespace es {

Undistorter::Undistorter(const ColmapCamera& camera,
                         const std::string& source) {
  const std::vector<double>& p = camera.params;
  // OpenCV's distortion order: k1 k2 p1 p2.
  double dist[4] = {0, 0, 0, 0};
  if (camera.model == "SIMPLE_PINHOLE" || camera.model == "SIMPLE_RADIAL" ||
      camera.model == "RADIAL") {
    CHECK_GE(p.size(), 3u);
    pinhole_.fx = pinhole_.fy = p[0];
    pinhole_.cx = p[1];
    pinhole_.cy = p[2];
    if (camera.model == "SIMPLE_RADIAL") dist[0] = p.at(3);
    if (camera.model == "RADIAL") {
      dist[0] = p.at(3);
      dist[1] = p.at(4);
    }
  } else if (camera.model == "PINHOLE" || camera.model == "OPENCV") {
    CHECK_GE(p.size(), 4u);
    pinhole_.fx = p[0];
    pinhole_.fy = p[1];
    pinhole_.cx = p[2];
    pinhole_.cy = p[3];
    if (camera.model == "OPENCV")
      for (int i = 0; i < 4; ++i) dist[i] = p.at(4 + i);
  } else {
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " uses the unsupported model " + camera.model +
                     " (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, "
                     "RADIAL, OPENCV)");
  }
  pinhole_.width = camera.width;
  pinhole_.height = camera.height;
  // The rasterizer divides by the focal length: a zero, negative or
  // non-finite one is the file's fault, reported here rather than failing a
  // CHECK mid-training.
  if (!(pinhole_.fx > 0) || !(pinhole_.fy > 0) || !std::isfinite(pinhole_.fx) ||
      !std::isfinite(pinhole_.fy) || !std::isfinite(pinhole_.cx) ||
      !std::isfinite(pinhole_.cy) || camera.width <= 0 || camera.height <= 0)
    throw InputError(source + ": camera " + std::to_string(camera.id) +
                     " has an invalid size or focal length (fx " +
                     std::to_string(pinhole_.fx) + ", fy " +
                     std::to_string(pinhole_.fy) + ")");
  std::copy(dist, dist + 4, dist_);
}

bool Undistorter::is_identity() const {
  return dist_[0] == 0 && dist_[1] == 0 && dist_[2] == 0 && dist_[3] == 0;
}

cv::Mat Undistorter::Apply(const cv::Mat& image) const {
  if (is_identity()) return image;
  CHECK_EQ(image.cols, pinhole_.width);
  CHECK_EQ(image.rows, pinhole_.height);
  if (map_x_.empty()) {
    // Built on first use, after the caller has checked a real frame of this
    // size: a corrupt camera size must not allocate maps for it first.
    // OpenCV puts pixel centers at integers, COLMAP at +0.5: shift the
    // principal point so both describe the same rays.
    const cv::Matx33d k(pinhole_.fx, 0, pinhole_.cx - 0.5, 0, pinhole_.fy,
                        pinhole_.cy - 0.5, 0, 0, 1);
    cv::initUndistortRectifyMap(
        k, cv::Mat(1, 4, CV_64F, const_cast<double*>(dist_)), cv::Mat(), k,
        cv::Size(pinhole_.width, pinhole_.height), CV_32FC1, map_x_, map_y_);
  }
  cv::Mat out;
  cv::remap(image, out, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace es
