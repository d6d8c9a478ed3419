// The device residual L2 loss against its CPU twin, ResidualL2Mean
// (costs/residual_l2_terms.h, what ResidualL2Loss runs): loss and
// d loss / d residuals on random outputs of several sizes (one value,
// around the block size, D's 52 outputs for an odd number of Gaussians),
// the known case of equal values, and no dynamic Gaussians at all. Skips
// when no CUDA device is present.

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/device_residual_l2_loss.h"
#include "costs/residual_l2_terms.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

constexpr int kOutputs = 52;  // D's outputs per Gaussian (kResidualDim)

struct LossAndGradient {
  double loss = 0;
  std::vector<double> grad;
};

LossAndGradient CpuLoss(const std::vector<double>& r, double scale) {
  LossAndGradient out;
  out.grad.assign(r.size(), 0.0);
  out.loss = ResidualL2Mean(r.data(), r.size(), scale, out.grad.data());
  return out;
}

LossAndGradient DeviceLoss(const std::vector<double>& r, double scale) {
  DeviceBuffer<double> dr, dgrad(r.size());
  dr.Upload(r);
  DeviceResidualL2Loss loss;
  LossAndGradient out;
  const long long count = static_cast<long long>(r.size());
  out.loss = loss.Evaluate(dr.data(), count, scale, dgrad.data());
  out.grad = dgrad.Download();
  // Without a gradient wanted, and again: the same loss, bit for bit.
  EXPECT_EQ(loss.Evaluate(dr.data(), count, scale, nullptr), out.loss);
  return out;
}

class DeviceResidualL2LossTest : public ::testing::TestWithParam<int> {};

TEST_P(DeviceResidualL2LossTest, MatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA residual L2 loss");
  const int count = GetParam();
  std::mt19937 rng(count);
  std::normal_distribution<double> normal(0, 0.05);
  std::vector<double> r(count);
  for (double& v : r) v = normal(rng);
  const double scale = 0.3;
  const LossAndGradient want = CpuLoss(r, scale);
  const LossAndGradient got = DeviceLoss(r, scale);
  // The squares summed in another order.
  EXPECT_NEAR(got.loss, want.loss, 1e-12 * want.loss);
  // The same double product per value.
  EXPECT_EQ(got.grad, want.grad);
}

INSTANTIATE_TEST_SUITE_P(Sizes, DeviceResidualL2LossTest,
                         ::testing::Values(1, 255, 256, 257, kOutputs * 7,
                                           kOutputs * 101),
                         [](const auto& info) {
                           return std::to_string(info.param);
                         });

// Equal values: the mean square is the value squared, the gradient
// 2 scale v / n.
TEST(DeviceResidualL2Loss, KnownAnswer) {
  ES_REQUIRE_GPU("CUDA residual L2 loss");
  const std::vector<double> r(kOutputs * 3, 0.5);
  const LossAndGradient got = DeviceLoss(r, 1.5);
  EXPECT_DOUBLE_EQ(got.loss, 0.25);
  for (double g : got.grad) EXPECT_DOUBLE_EQ(g, 2 * 1.5 * 0.5 / r.size());
}

// No dynamic Gaussians: loss 0 as on the CPU, nothing launched.
TEST(DeviceResidualL2Loss, Empty) {
  ES_REQUIRE_GPU("CUDA residual L2 loss");
  DeviceResidualL2Loss loss;
  EXPECT_EQ(loss.Evaluate(nullptr, 0, 1.0, nullptr), 0.0);
  EXPECT_EQ(ResidualL2Mean(nullptr, 0, 1.0, nullptr), 0.0);
}

}  // namespace
}  // namespace cuda
}  // namespace es
