// The device photometric loss against its CPU twin: SSIM in float on plain
// arrays (core/metrics/ssim_target.h, what PhotometricLoss runs in
// training) fused with L1 and combined with the SSIM weight as
// costs/photometric_loss.cc does, and the CPU's L1 alone when the weight is
// 0. Loss and d loss / d image on random images of several sizes (smaller
// than the window, not multiples of the block size), and the known case of
// identical images. Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/metrics/ssim_target.h"
#include "core/base/cuda/cuda_error.h"
#include "tests/cuda/host_arrays.h"
#include "tests/cuda/require_gpu.h"
#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/device_photometric_loss.h"

namespace es {
namespace cuda {
namespace {

struct LossAndGradient {
  double loss = 0, l1 = 0, ssim = 1;
  std::vector<double> grad;
};

// PhotometricLoss::Evaluate with use_double false, on float images.
LossAndGradient CpuLoss(const std::vector<float>& x,
                        const std::vector<float>& y, int width, int height,
                        double ssim_weight, double scale) {
  LossAndGradient out;
  const size_t n = x.size();
  const std::vector<double> xd(x.begin(), x.end());
  out.grad.assign(n, 0.0);
  const double a = scale * (1 - ssim_weight);
  if (ssim_weight != 0) {
    SsimScratch<float> scratch;
    SsimTarget<float> target;
    ComputeSsimTarget(y.data(), height, width, 3, &scratch, &target);
    out.ssim = SsimAndL1AgainstTarget(xd.data(), target, &scratch,
                                      -scale * ssim_weight, a,
                                      out.grad.data(), &out.l1);
  } else {
    const double inv_n = 1.0 / static_cast<double>(n);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
      const double diff = xd[i] - y[i];
      sum += std::abs(diff);
      out.grad[i] += a * inv_n * ((diff > 0) - (diff < 0));
    }
    out.l1 = sum * inv_n;
  }
  out.loss = (1 - ssim_weight) * out.l1 + ssim_weight * (1 - out.ssim);
  return out;
}

LossAndGradient DeviceLoss(const std::vector<float>& x,
                           const std::vector<float>& y, int width,
                           int height, double ssim_weight, double scale) {
  DeviceBuffer<float> dx, dy, dgrad(x.size());
  dx.Upload(x);
  dy.Upload(y);
  DevicePhotometricLoss loss(ssim_weight);
  LossAndGradient out;
  out.loss = loss.Evaluate(dx.data(), dy.data(), width, height, scale,
                           dgrad.data());
  out.l1 = loss.l1();
  out.ssim = loss.ssim();
  const std::vector<float> g = dgrad.Download();
  out.grad.assign(g.begin(), g.end());
  // Without a gradient wanted, the same loss.
  EXPECT_EQ(loss.Evaluate(dx.data(), dy.data(), width, height, scale,
                          nullptr),
            out.loss);
  return out;
}

std::vector<float> RandomImage(int width, int height, std::mt19937* rng) {
  std::uniform_real_distribution<float> uni(0, 1);
  std::vector<float> image(3 * static_cast<size_t>(width) * height);
  for (float& v : image) v = uni(*rng);
  return image;
}

// (width, height, SSIM weight)
class DevicePhotometricLossTest
    : public ::testing::TestWithParam<std::tuple<int, int, double>> {};

TEST_P(DevicePhotometricLossTest, MatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA photometric loss");
  const auto [width, height, ssim_weight] = GetParam();
  std::mt19937 rng(width * 131 + height);
  const std::vector<float> x = RandomImage(width, height, &rng);
  const std::vector<float> y = RandomImage(width, height, &rng);
  const double scale = 0.7;
  const LossAndGradient want =
      CpuLoss(x, y, width, height, ssim_weight, scale);
  const LossAndGradient got =
      DeviceLoss(x, y, width, height, ssim_weight, scale);
  EXPECT_NEAR(got.l1, want.l1, 1e-6 * want.l1);
  // Float sums and (on a device) fused multiply-adds: under 1e-7 of the
  // loss and 1e-6 of the largest gradient here under the emulation.
  EXPECT_NEAR(got.ssim, want.ssim, 1e-6);
  EXPECT_NEAR(got.loss, want.loss, 1e-6 * want.loss);
  EXPECT_LE(RelativeError(got.grad, want.grad), 1e-5);
}

INSTANTIATE_TEST_SUITE_P(
    Sizes, DevicePhotometricLossTest,
    ::testing::Values(std::make_tuple(4, 3, 0.2),     // under the window
                      std::make_tuple(11, 7, 0.2),    // window-wide
                      std::make_tuple(23, 17, 0.2),   // 1173 values
                      std::make_tuple(40, 26, 0.2),   // 3120 values
                      std::make_tuple(37, 29, 1.0),   // SSIM only
                      std::make_tuple(37, 29, 0.0)),  // L1 only
    [](const auto& info) {
      return std::to_string(std::get<0>(info.param)) + "x" +
             std::to_string(std::get<1>(info.param)) + "_ssim" +
             std::to_string(static_cast<int>(10 * std::get<2>(info.param)));
    });

// Identical images: L1 0, SSIM 1 and the SSIM term's gradient 0 (SSIM's
// maximum), on the device as on the CPU.
TEST(DevicePhotometricLoss, IdenticalImages) {
  ES_REQUIRE_GPU("CUDA photometric loss");
  const int width = 29, height = 19;
  std::mt19937 rng(7);
  const std::vector<float> x = RandomImage(width, height, &rng);
  const LossAndGradient got = DeviceLoss(x, x, width, height, 1.0, 1.0);
  const LossAndGradient cpu = CpuLoss(x, x, width, height, 1.0, 1.0);
  EXPECT_EQ(got.l1, 0.0);
  EXPECT_NEAR(got.ssim, 1.0, 1e-6);
  EXPECT_NEAR(got.loss, 0.0, 1e-6);
  // One value's gradient terms are about 1 / n each; they cancel.
  const double n = static_cast<double>(x.size());
  double largest = 0, largest_cpu = 0;
  for (double g : got.grad) largest = std::max(largest, std::abs(g));
  for (double g : cpu.grad) largest_cpu = std::max(largest_cpu, std::abs(g));
  EXPECT_LT(largest * n, 1e-4);
  EXPECT_LT(largest_cpu * n, 1e-4);
}

}  // namespace
}  // namespace cuda
}  // namespace es
