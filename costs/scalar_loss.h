#ifndef EULERSPLAT_COSTS_SCALAR_LOSS_H_
#define EULERSPLAT_COSTS_SCALAR_LOSS_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace es {

// A scalar loss l >= 0 is exposed to Ceres as one residual r = sqrt(2 l + eps)
// so that 0.5 r^2 = l (+ const) and J^T r = dl/dtheta: Problem::Evaluate's
// gradient is then exactly the loss gradient and ScaledLoss its weight. eps
// keeps dr/dtheta = (dl/dtheta) / r finite at l = 0.
constexpr double kScalarLossEps = 1e-12;

inline double ScalarLossResidual(double loss) {
  return std::sqrt(2.0 * loss + kScalarLossEps);
}

// Writes the Jacobian row dr/dtheta = (dl/dtheta) / r of one block.
inline void ScalarLossJacobian(const double* dl, int n, double residual,
                               double* jacobian) {
  const double inv = 1.0 / residual;
  for (int i = 0; i < n; ++i) jacobian[i] = dl[i] * inv;
}

// Evaluates a scalar-loss cost straight into gradient buffers (one per
// parameter block, sized like it; the trainers' path, which skips
// Problem::Evaluate's per-parameter overhead): the Jacobian row written
// there is multiplied back by r, leaving dl/dtheta, by scale(size, r,
// block), which scales a block where it lives (host or device memory).
// Returns 0.5 r^2 = l + eps / 2.
template <typename Scale>
double EvaluateScalarLossGradientWith(const ceres::CostFunction& cost,
                                      double const* const* parameters,
                                      double** gradients, Scale scale) {
  CHECK_EQ(cost.num_residuals(), 1);
  double r = 0;
  CHECK(cost.Evaluate(parameters, &r, gradients));
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  for (size_t b = 0; b < sizes.size(); ++b) scale(sizes[b], r, gradients[b]);
  return 0.5 * r * r;
}

// The same on host buffers.
inline double EvaluateScalarLossGradient(const ceres::CostFunction& cost,
                                         double const* const* parameters,
                                         double** gradients) {
  return EvaluateScalarLossGradientWith(
      cost, parameters, gradients, [](int size, double r, double* block) {
#pragma omp parallel for if (size > 65536) schedule(static)
        for (int i = 0; i < size; ++i) block[i] *= r;
      });
}

}  // namespace es

#endif  // EULERSPLAT_COSTS_SCALAR_LOSS_H_
