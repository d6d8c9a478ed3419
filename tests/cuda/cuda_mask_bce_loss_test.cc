// The device mask BCE loss against its CPU twin, MaskBceMean
// (costs/mask_bce_terms.h, what MaskBceLoss runs on a CV_32F mask), fed
// the same float probabilities as doubles: loss and d loss / d probability
// on random images of several sizes (one pixel, not multiples of the block
// size, fractional masks), in the rasterizer's extra-channel layout with
// one channel and with the probability among three, and the clamp's edge
// cases (probabilities and masks at exactly 0 and 1) with their known
// values. Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/device_mask_bce_loss.h"
#include "costs/mask_bce_terms.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

// Written into the channels the loss must leave alone.
constexpr float kUntouched = -7.0f;

struct LossAndGradient {
  double loss = 0;
  std::vector<double> grad;  // per pixel
};

LossAndGradient CpuLoss(const std::vector<float>& probability,
                        const std::vector<float>& mask, double scale) {
  const std::vector<double> p(probability.begin(), probability.end());
  LossAndGradient out;
  out.grad.assign(p.size(), 0.0);
  out.loss = MaskBceMean(p.data(), mask.data(), static_cast<int>(p.size()),
                         scale, out.grad.data());
  return out;
}

// The probabilities go into channel `channel` of `num_extra`.
LossAndGradient DeviceLoss(const std::vector<float>& probability,
                           const std::vector<float>& mask, int width,
                           int height, int num_extra, int channel,
                           double scale) {
  const size_t pixels = probability.size();
  std::vector<float> extra(pixels * num_extra, 0.5f);
  for (size_t i = 0; i < pixels; ++i)
    extra[i * num_extra + channel] = probability[i];
  DeviceBuffer<float> dextra, dmask, dgrad;
  dextra.Upload(extra);
  dmask.Upload(mask);
  dgrad.Upload(std::vector<float>(extra.size(), kUntouched));
  DeviceMaskBceLoss loss;
  LossAndGradient out;
  out.loss = loss.Evaluate(dextra.data(), num_extra, channel, dmask.data(),
                           width, height, scale, dgrad.data());
  const std::vector<float> g = dgrad.Download();
  for (size_t i = 0; i < pixels; ++i) {
    out.grad.push_back(g[i * num_extra + channel]);
    for (int e = 0; e < num_extra; ++e) {
      if (e == channel) continue;
      EXPECT_EQ(g[i * num_extra + e], kUntouched);
    }
  }
  // Without a gradient wanted, and again: the same loss, bit for bit.
  EXPECT_EQ(loss.Evaluate(dextra.data(), num_extra, channel, dmask.data(),
                          width, height, scale, nullptr),
            out.loss);
  return out;
}

// Probabilities in [0, 1] with some exactly 0 or 1 and some inside the
// clamp's margin; masks mostly 0 or 1, some in between.
void RandomInputs(int pixels, std::mt19937* rng,
                  std::vector<float>* probability, std::vector<float>* mask) {
  std::uniform_real_distribution<float> uni(0, 1);
  std::uniform_int_distribution<int> pick(0, 9);
  probability->resize(pixels);
  mask->resize(pixels);
  for (int i = 0; i < pixels; ++i) {
    const int k = pick(*rng);
    (*probability)[i] = k == 0   ? 0.0f
                        : k == 1 ? 1.0f
                        : k == 2 ? 1e-7f
                        : k == 3 ? 1.0f - 1e-7f
                                 : uni(*rng);
    const int m = pick(*rng);
    (*mask)[i] = m < 4 ? 0.0f : m < 8 ? 1.0f : uni(*rng);
  }
}

// Each device gradient is the CPU's double rounded to float (the same
// double operations), and 0 exactly where the CPU's is.
void ExpectGradientsMatch(const LossAndGradient& got,
                          const LossAndGradient& want) {
  ASSERT_EQ(got.grad.size(), want.grad.size());
  for (size_t i = 0; i < want.grad.size(); ++i) {
    if (want.grad[i] == 0) {
      EXPECT_EQ(got.grad[i], 0.0) << "pixel " << i;
    } else {
      EXPECT_FLOAT_EQ(static_cast<float>(got.grad[i]),
                      static_cast<float>(want.grad[i]))
          << "pixel " << i;
    }
  }
}

// (width, height, num_extra, channel)
class DeviceMaskBceLossTest
    : public ::testing::TestWithParam<std::tuple<int, int, int, int>> {};

TEST_P(DeviceMaskBceLossTest, MatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA mask BCE loss");
  const auto [width, height, num_extra, channel] = GetParam();
  std::mt19937 rng(width * 131 + height);
  std::vector<float> probability, mask;
  RandomInputs(width * height, &rng, &probability, &mask);
  const double scale = 0.3;
  const LossAndGradient want = CpuLoss(probability, mask, scale);
  const LossAndGradient got = DeviceLoss(probability, mask, width, height,
                                         num_extra, channel, scale);
  // Double terms summed in another order.
  EXPECT_NEAR(got.loss, want.loss, 1e-12 * want.loss);
  ExpectGradientsMatch(got, want);
}

INSTANTIATE_TEST_SUITE_P(
    Sizes, DeviceMaskBceLossTest,
    ::testing::Values(std::make_tuple(1, 1, 1, 0),     // one pixel
                      std::make_tuple(4, 3, 1, 0),     // under a block
                      std::make_tuple(23, 17, 1, 0),   // 391 pixels
                      std::make_tuple(40, 26, 1, 0),   // 1040 pixels
                      std::make_tuple(97, 61, 1, 0),   // 5917 pixels
                      std::make_tuple(37, 29, 3, 1)),  // among 3 channels
    [](const auto& info) {
      return std::to_string(std::get<0>(info.param)) + "x" +
             std::to_string(std::get<1>(info.param)) + "_channel" +
             std::to_string(std::get<3>(info.param)) + "of" +
             std::to_string(std::get<2>(info.param));
    });

// Probabilities and masks at exactly 0 and 1: the clamp keeps the loss
// finite (-log of the margin where they disagree, -log(1 - margin) where
// they agree) and the gradient 0, as on the CPU.
TEST(DeviceMaskBceLoss, ClampedEdges) {
  ES_REQUIRE_GPU("CUDA mask BCE loss");
  const std::vector<float> probability = {0, 0, 1, 1, 0.25f};
  const std::vector<float> mask = {0, 1, 0, 1, 1};
  const LossAndGradient got = DeviceLoss(probability, mask, 5, 1, 1, 0, 2);
  const LossAndGradient want = CpuLoss(probability, mask, 2);
  const double agree = -std::log(1 - kMaskProbabilityMargin);
  const double disagree = -std::log(kMaskProbabilityMargin);
  const double known = (2 * agree + 2 * disagree - std::log(0.25)) / 5;
  EXPECT_NEAR(got.loss, known, 1e-12 * known);
  EXPECT_NEAR(want.loss, known, 1e-12 * known);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(got.grad[i], 0.0) << "pixel " << i;
  // Unclamped: scale / n * (-t / p) = 2 / 5 * -4.
  EXPECT_FLOAT_EQ(static_cast<float>(got.grad[4]), -1.6f);
  ExpectGradientsMatch(got, want);
}

}  // namespace
}  // namespace cuda
}  // namespace es
