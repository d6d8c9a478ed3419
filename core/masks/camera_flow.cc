#include "core/masks/camera_flow.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace es {

cv::Mat CameraFlow(const cv::Mat& depth, const Camera& a, const Camera& b) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat out(depth.size(), CV_32FC2, cv::Scalar(nan, nan));
  const Eigen::Matrix3d r_a = a.R(), r_b = b.R();
#pragma omp parallel for schedule(static)
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      const float z = depth.at<float>(y, x);
      if (z <= 0) continue;
      const Eigen::Vector3d world =
          r_a.transpose() * (a.Unproject(x + 0.5, y + 0.5, z) - a.t_cw);
      const Eigen::Vector3d in_b = r_b * world + b.t_cw;
      if (in_b.z() <= 1e-6) continue;
      const Eigen::Vector2d uv = b.Project(in_b);
      out.at<cv::Vec2f>(y, x) = {static_cast<float>(uv.x() - x - 0.5),
                                 static_cast<float>(uv.y() - y - 0.5)};
    }
  }
  return out;
}

void CarryByCameraFlow(const cv::Mat& image, const cv::Mat& camera_flow,
                       cv::Mat* out, cv::Mat* known) {
  cv::Mat map(camera_flow.size(), CV_32FC2);
  *known = cv::Mat(camera_flow.size(), CV_8UC1, cv::Scalar(1));
  for (int y = 0; y < map.rows; ++y)
    for (int x = 0; x < map.cols; ++x) {
      const cv::Vec2f c = camera_flow.at<cv::Vec2f>(y, x);
      const cv::Vec2f m(x + c[0], y + c[1]);
      map.at<cv::Vec2f>(y, x) = m;
      // NaN fails every comparison: unknown too.
      if (!(m[0] >= 0 && m[1] >= 0 && m[0] <= image.cols - 1 &&
            m[1] <= image.rows - 1))
        known->at<uchar>(y, x) = 0;
    }
  cv::remap(image, *out, map, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REPLICATE);
}

cv::Mat TolerantDifference(const cv::Mat& image, const cv::Mat& other,
                           int radius) {
  cv::Mat lo = other, hi = other;
  if (radius > 0) {
    const cv::Mat square = cv::getStructuringElement(
        cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::erode(other, lo, square, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    cv::dilate(other, hi, square, cv::Point(-1, -1), 1,
               cv::BORDER_REPLICATE);
  }
  cv::Mat above, below, out;
  cv::subtract(image, hi, above);
  cv::subtract(lo, image, below);
  cv::transform(cv::max(above, 0.f) + cv::max(below, 0.f), out,
                cv::Matx13f(1 / 3.f, 1 / 3.f, 1 / 3.f));
  return out;
}

}  // namespace es
