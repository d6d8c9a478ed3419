#ifndef EULERSPLAT_TESTS_LOSS_GRADIENT_H_
#define EULERSPLAT_TESTS_LOSS_GRADIENT_H_

#include <algorithm>
#include <cmath>
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

// Expects Problem::Evaluate's flat gradient to hold the per-block gradient
// `blocks`, within `relative_tolerance` of its largest entry (not zero).
inline void ExpectSameGradient(const std::vector<double>& flat,
                               const std::vector<std::vector<double>>& blocks,
                               double relative_tolerance) {
  size_t offset = 0;
  double max_err = 0, max_abs = 0;
  for (const auto& block : blocks)
    for (double v : block) {
      max_err = std::max(max_err, std::abs(flat[offset++] - v));
      max_abs = std::max(max_abs, std::abs(v));
    }
  EXPECT_EQ(offset, flat.size());
  EXPECT_GT(max_abs, 0.0);
  EXPECT_LT(max_err, relative_tolerance * max_abs);
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_LOSS_GRADIENT_H_
