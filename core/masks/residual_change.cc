#include "core/masks/residual_change.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/masks/camera_flow.h"

namespace es {
namespace {

// |a - b carried back to a by camera_flow|, mean over channels, with
// `tolerance` pixels of slack (TolerantDifference); -1 where the flow is
// unknown or leaves b.
cv::Mat CarriedDifference(const cv::Mat& a, const cv::Mat& b,
                          const cv::Mat& camera_flow, int tolerance) {
  cv::Mat carried, known;
  CarryByCameraFlow(b, camera_flow, &carried, &known);
  cv::Mat out = TolerantDifference(a, carried, tolerance);
  out.setTo(-1, known == 0);
  return out;
}

}  // namespace

std::vector<cv::Mat> ResidualChange(const std::vector<ResidualFrame>& frames,
                                    const ResidualChangeOptions& options) {
  CHECK_GT(options.gap, 0);
  CHECK_GT(options.partners, 0);
  const int n = static_cast<int>(frames.size());
  std::map<int, int> by_time;
  for (int i = 0; i < n; ++i) by_time[frames[i].time_index] = i;

  std::vector<cv::Mat> change(n);
  std::vector<cv::Mat> diffs;
  std::vector<float> values;
  for (int i = 0; i < n; ++i) {
    const ResidualFrame& f = frames[i];
    diffs.clear();
    for (int k = 1; k <= options.partners; ++k)
      for (int side : {-1, 1}) {
        const auto it = by_time.find(f.time_index + side * k * options.gap);
        if (it == by_time.end()) continue;
        const ResidualFrame& other = frames[it->second];
        diffs.push_back(CarriedDifference(
            f.residual, other.residual,
            CameraFlow(f.depth, f.camera, other.camera), options.tolerance));
      }
    change[i] = cv::Mat(f.residual.size(), CV_32FC1, cv::Scalar(-1.f));
    for (int p = 0; p < static_cast<int>(change[i].total()); ++p) {
      values.clear();
      for (const cv::Mat& d : diffs) {
        const float v = d.at<float>(p);
        if (v >= 0) values.push_back(v);
      }
      if (static_cast<int>(values.size()) < options.min_partners) continue;
      // The lower median: of two comparisons, the smaller.
      auto mid = values.begin() + (values.size() - 1) / 2;
      std::nth_element(values.begin(), mid, values.end());
      change[i].at<float>(p) = *mid;
    }
  }
  return change;
}

}  // namespace es
