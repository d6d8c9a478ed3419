#include "costs/mask_bce_loss.h"

#include <glog/logging.h>

#include <cmath>

namespace es {

double MaskBceLoss(const double* probability, const cv::Mat& mask, double scale,
                   double* d_probability) {
  CHECK_EQ(mask.channels(), 1);
  cv::Mat m;
  mask.convertTo(m, CV_64F);
  const double* pm = m.ptr<double>();
  const int n = m.rows * m.cols;
  const double inv_n = 1.0 / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double raw = probability[i];
    const double p = std::min(std::max(raw, kMaskProbabilityMargin),
                              1.0 - kMaskProbabilityMargin);
    const double t = pm[i];
    sum -= t * std::log(p) + (1 - t) * std::log(1 - p);
    if (d_probability) {
      d_probability[i] =
          p == raw ? scale * inv_n * ((1 - t) / (1 - p) - t / p) : 0.0;
    }
  }
  return sum * inv_n;
}

}  // namespace es
