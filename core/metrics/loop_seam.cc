#include "core/metrics/loop_seam.h"

#include <cmath>
#include <limits>

#include <glog/logging.h>

namespace es {
namespace {

double MeanAbsoluteChange(const cv::Mat& a, const cv::Mat& b,
                          const cv::Mat& mask) {
  cv::Mat a64, b64, diff;
  a.convertTo(a64, CV_64F);
  b.convertTo(b64, CV_64F);
  cv::absdiff(a64, b64, diff);
  if (mask.empty()) {
    return cv::sum(diff.reshape(1)).val[0] / diff.total() / diff.channels();
  }
  if (cv::countNonZero(mask) == 0) return 0.0;
  const cv::Scalar masked = cv::mean(diff, mask);
  double total = 0;
  for (int c = 0; c < diff.channels(); ++c) total += masked.val[c];
  return total / diff.channels();
}

}  // namespace

LoopSeamScore ComputeLoopSeam(const std::vector<cv::Mat>& frames,
                              int cycle_length, int first_frame,
                              const cv::Mat& mask) {
  CHECK_GT(cycle_length, 0);
  CHECK_GE(first_frame, 0);
  cv::Mat mask8;
  if (!mask.empty()) {
    CHECK_EQ(mask.channels(), 1);
    CHECK(frames.empty() || mask.size() == frames[0].size());
    const double threshold = mask.depth() == CV_8U ? 127 : 0.5;
    mask8 = mask > threshold;
  }
  LoopSeamScore s;
  for (size_t k = 0; k + 1 < frames.size(); ++k) {
    CHECK(frames[k + 1].size() == frames[0].size() &&
          frames[k + 1].type() == frames[0].type());
    const double change = MeanAbsoluteChange(frames[k], frames[k + 1], mask8);
    const long long next = first_frame + static_cast<long long>(k) + 1;
    if (next % cycle_length == 0) {
      s.boundary_change += change;
      ++s.boundary_pairs;
    } else {
      s.within_change += change;
      ++s.within_pairs;
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (s.boundary_pairs == 0 || s.within_pairs == 0) {
    s.boundary_change = s.boundary_pairs ? s.boundary_change / s.boundary_pairs
                                         : nan;
    s.within_change = s.within_pairs ? s.within_change / s.within_pairs : nan;
    s.score = nan;
    return s;
  }
  s.boundary_change /= s.boundary_pairs;
  s.within_change /= s.within_pairs;
  if (s.within_change > 0) {
    s.score = s.boundary_change / s.within_change;
  } else {
    s.score = s.boundary_change > 0
                  ? std::numeric_limits<double>::infinity()
                  : 1.0;  // a still image: no seam
  }
  return s;
}

}  // namespace es
