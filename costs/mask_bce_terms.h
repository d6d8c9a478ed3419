#ifndef EULERSPLAT_COSTS_MASK_BCE_TERMS_H_
#define EULERSPLAT_COSTS_MASK_BCE_TERMS_H_

// The mask BCE loss on plain arrays, without OpenCV: what MaskBceLoss
// (costs/mask_bce_loss.h) computes, and the CPU twin of the device loss
// (costs/cuda/device_mask_bce_loss.h).

#include <algorithm>
#include <cmath>

namespace es {

// Probabilities are clamped to this margin from 0 and 1 so the log stays
// finite; where the clamp is active the gradient is zero.
constexpr double kMaskProbabilityMargin = 1e-6;

// Mean over n values of the binary cross-entropy of probability[i] against
// target[i] in [0, 1]; if d_probability is not null it receives
// scale * dl / d probability.
template <typename T>
double MaskBceMean(const double* probability, const T* target, int n,
                   double scale, double* d_probability) {
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

}  // namespace es

#endif  // EULERSPLAT_COSTS_MASK_BCE_TERMS_H_
