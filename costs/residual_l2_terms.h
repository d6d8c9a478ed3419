#ifndef EULERSPLAT_COSTS_RESIDUAL_L2_TERMS_H_
#define EULERSPLAT_COSTS_RESIDUAL_L2_TERMS_H_

// The residual L2 loss on a plain array, without Ceres: what
// ResidualL2Loss (costs/residual_l2_cost.h) computes, and the CPU twin of
// the device loss (costs/cuda/device_residual_l2_loss.h).

#include <cstddef>

namespace es {

// Mean of the n values' squares (0 when n is 0); if d_residuals is not
// null it receives scale * dl / d residuals.
inline double ResidualL2Mean(const double* residuals, size_t n, double scale,
                             double* d_residuals) {
  if (n == 0) return 0.0;
  const double inv = 1.0 / static_cast<double>(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += residuals[i] * residuals[i];
  if (d_residuals != nullptr) {
    const double g = 2.0 * scale * inv;
    for (size_t i = 0; i < n; ++i) d_residuals[i] = g * residuals[i];
  }
  return sum * inv;
}

}  // namespace es

#endif  // EULERSPLAT_COSTS_RESIDUAL_L2_TERMS_H_
