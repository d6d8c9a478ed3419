#ifndef EULERSPLAT_COSTS_SCALAR_LOSS_H_
#define EULERSPLAT_COSTS_SCALAR_LOSS_H_

#include <cmath>

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

}  // namespace es

#endif  // EULERSPLAT_COSTS_SCALAR_LOSS_H_
