#include "costs/mask_bce_loss.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>

#include "core/profile/stage_profile.h"

namespace es {

namespace {

template <typename T>
double Bce(const double* probability, const T* target, int n, double scale,
           double* d_probability) {
  const double inv_n = 1.0 / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double raw = probability[i];
    const double p = std::min(std::max(raw, kMaskProbabilityMargin),
                              1.0 - kMaskProbabilityMargin);
    const double t = target[i];
    // Masks are mostly exactly 0 or 1: one logarithm then, not two.
    if (t == 0) {
      sum -= std::log(1 - p);
    } else if (t == 1) {
      sum -= std::log(p);
    } else {
      sum -= t * std::log(p) + (1 - t) * std::log(1 - p);
    }
    if (d_probability) {
      d_probability[i] =
          p == raw ? scale * inv_n * ((1 - t) / (1 - p) - t / p) : 0.0;
    }
  }
  return sum * inv_n;
}

}  // namespace

double MaskBceLoss(const double* probability, const cv::Mat& mask, double scale,
                   double* d_probability) {
  ScopedStage timer(Stage::kLossBce);
  CHECK_EQ(mask.channels(), 1);
  const int n = mask.rows * mask.cols;
  // Read in place (no per-call conversion) in the mask types frames hold.
  if (mask.isContinuous() && mask.depth() == CV_32F)
    return Bce(probability, mask.ptr<float>(), n, scale, d_probability);
  if (mask.isContinuous() && mask.depth() == CV_64F)
    return Bce(probability, mask.ptr<double>(), n, scale, d_probability);
  cv::Mat m;
  mask.convertTo(m, CV_64F);
  return Bce(probability, m.ptr<double>(), n, scale, d_probability);
}

}  // namespace es
