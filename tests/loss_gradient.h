#ifndef EULERSPLAT_TESTS_LOSS_GRADIENT_H_
#define EULERSPLAT_TESTS_LOSS_GRADIENT_H_

#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "costs/scalar_loss.h"

namespace es {

// Gradient of the loss (not the residual) per block by calling Evaluate
// directly, as the trainers do: dl/dtheta = J r.
inline std::vector<std::vector<double>> LossGradient(
    const ceres::CostFunction& cost, const std::vector<double*>& blocks,
    double* loss) {
  std::vector<std::vector<double>> jac;
  std::vector<double*> jac_ptrs;
  for (int size : cost.parameter_block_sizes()) jac.emplace_back(size);
  for (auto& j : jac) jac_ptrs.push_back(j.data());
  double r = 0;
  EXPECT_TRUE(cost.Evaluate(blocks.data(), &r, jac_ptrs.data()));
  for (auto& j : jac)
    for (double& v : j) v *= r;
  *loss = 0.5 * (r * r - kScalarLossEps);
  return jac;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_LOSS_GRADIENT_H_
