// The device water energy loss against its CPU twin (WaterEnergyLoss):
// the loss, both unweighted terms and both images' gradients on random
// images of odd sizes (border and indexing bugs), with and without masks,
// one to three detail bands (the coarse bands' windows wider than the
// image), weights other than 1 and 0; gradients added (+=) to non-zero
// arrays; a flat render (the eps floor keeps its gradient finite); and a
// central difference of the device loss at two pixels. Double on both sides,
// summed in another order; the gradients come back as floats. Skips when
// no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/device_water_energy_loss.h"
#include "costs/water_energy_loss.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/host_arrays.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

// Two frames, rendered and input, and (maybe) their masks: host floats.
struct Pair {
  int width = 0, height = 0;
  std::vector<float> rendered_a, rendered_b, input_a, input_b;
  std::vector<float> mask_a, mask_b;  // empty: no masks
};

std::vector<float> Random(size_t n, float lo, float hi, std::mt19937* rng) {
  std::uniform_real_distribution<float> uni(lo, hi);
  std::vector<float> v(n);
  for (float& x : v) x = uni(*rng);
  return v;
}

Pair RandomPair(int width, int height, bool masks, uint32_t seed) {
  std::mt19937 rng(seed);
  Pair p;
  p.width = width;
  p.height = height;
  const size_t n = 3 * static_cast<size_t>(width) * height;
  p.rendered_a = Random(n, 0, 1, &rng);
  p.rendered_b = Random(n, 0, 1, &rng);
  p.input_a = Random(n, 0, 1, &rng);
  p.input_b = Random(n, 0, 1, &rng);
  if (masks) {  // values around the 0.5 threshold too
    p.mask_a = Random(n / 3, 0, 1, &rng);
    p.mask_b = Random(n / 3, 0, 1, &rng);
  }
  return p;
}

struct Result {
  double loss = 0;
  WaterEnergyTerms terms;
  std::vector<double> d_a, d_b;  // the gradients added
};

cv::Mat Image(const std::vector<float>& v, int width, int height,
              int channels) {
  if (v.empty()) return cv::Mat();
  return cv::Mat(height, width, CV_32FC(channels),
                 const_cast<float*>(v.data()));
}

Result CpuLoss(const Pair& p, const WaterEnergyOptions& options,
               double scale) {
  const std::vector<double> ra(p.rendered_a.begin(), p.rendered_a.end());
  const std::vector<double> rb(p.rendered_b.begin(), p.rendered_b.end());
  Result r;
  r.d_a.assign(ra.size(), 0.0);
  r.d_b.assign(rb.size(), 0.0);
  WaterEnergyLoss loss(options);
  r.loss = loss.Evaluate(
      ra.data(), rb.data(), Image(p.input_a, p.width, p.height, 3),
      Image(p.input_b, p.width, p.height, 3),
      Image(p.mask_a, p.width, p.height, 1),
      Image(p.mask_b, p.width, p.height, 1), scale, r.d_a.data(),
      r.d_b.data(), &r.terms);
  return r;
}

// A pair's images and masks on the device.
struct DevicePair {
  DeviceBuffer<float> ra, rb, ia, ib, ma, mb;

  explicit DevicePair(const Pair& p) {
    ra.Upload(p.rendered_a);
    rb.Upload(p.rendered_b);
    ia.Upload(p.input_a);
    ib.Upload(p.input_b);
    if (!p.mask_a.empty()) {
      ma.Upload(p.mask_a);
      mb.Upload(p.mask_b);
    }
  }
  double Evaluate(const Pair& p, DeviceWaterEnergyLoss* loss, double scale,
                  float* d_a, float* d_b, WaterEnergyTerms* terms) const {
    const bool masks = !p.mask_a.empty();
    return loss->Evaluate(ra.data(), rb.data(), ia.data(), ib.data(),
                          masks ? ma.data() : nullptr,
                          masks ? mb.data() : nullptr, p.width, p.height,
                          scale, d_a, d_b, terms);
  }
};

// The device loss, its gradients added to d_a0 / d_b0 (returned less
// those, in double). With check_loss_alone, evaluated again without
// gradients.
Result DeviceLoss(const Pair& p, const WaterEnergyOptions& options,
                  double scale, const std::vector<float>& d_a0,
                  const std::vector<float>& d_b0,
                  bool check_loss_alone = false) {
  const DevicePair images(p);
  DeviceBuffer<float> da, db;
  da.Upload(d_a0);
  db.Upload(d_b0);
  DeviceWaterEnergyLoss loss(options);
  Result r;
  r.loss = images.Evaluate(p, &loss, scale, da.data(), db.data(), &r.terms);
  const std::vector<float> got_a = da.Download(), got_b = db.Download();
  for (size_t i = 0; i < got_a.size(); ++i) {
    r.d_a.push_back(static_cast<double>(got_a[i]) - d_a0[i]);
    r.d_b.push_back(static_cast<double>(got_b[i]) - d_b0[i]);
  }
  if (!check_loss_alone) return r;
  // Without gradients wanted, the same loss, bit for bit (the same sums in
  // the same order).
  WaterEnergyTerms terms;
  EXPECT_EQ(images.Evaluate(p, &loss, scale, nullptr, nullptr, &terms),
            r.loss);
  EXPECT_EQ(terms.motion, r.terms.motion);
  EXPECT_EQ(terms.detail, r.terms.detail);
  return r;
}

double Largest(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Loss and terms in double on both sides: within 1e-10 relative. The
// gradients are floats on the device, added to values of their own size:
// within 1e-6 of the largest.
void ExpectTwins(const Result& got, const Result& want) {
  EXPECT_NEAR(got.loss, want.loss, 1e-10 * std::abs(want.loss));
  EXPECT_NEAR(got.terms.motion, want.terms.motion,
              1e-10 * std::abs(want.terms.motion));
  EXPECT_NEAR(got.terms.detail, want.terms.detail,
              1e-10 * std::abs(want.terms.detail));
  ExpectSomeNonZero(want.d_a, "CPU d_a");
  ExpectSomeNonZero(want.d_b, "CPU d_b");
  EXPECT_LE(RelativeError(got.d_a, want.d_a), 1e-6);
  EXPECT_LE(RelativeError(got.d_b, want.d_b), 1e-6);
  // The measured errors, for the XML report (--gtest_output=xml).
  std::ostringstream errors;
  errors << std::scientific << "loss "
         << std::abs(got.loss - want.loss) / std::abs(want.loss)
         << ", gradients "
         << std::max(RelativeError(got.d_a, want.d_a),
                     RelativeError(got.d_b, want.d_b));
  ::testing::Test::RecordProperty("relative_errors", errors.str());
}

// Non-zero starting gradients of the CPU's gradients' size, so that +=
// is checked (an = would lose them).
std::vector<float> Start(size_t n, double size, uint32_t seed) {
  std::mt19937 rng(seed);
  return Random(n, static_cast<float>(-size), static_cast<float>(size), &rng);
}

// (width, height, masks, detail octaves)
class DeviceWaterEnergyLossTest
    : public ::testing::TestWithParam<std::tuple<int, int, bool, int>> {};

TEST_P(DeviceWaterEnergyLossTest, MatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA water energy loss");
  const auto [width, height, masks, octaves] = GetParam();
  const Pair p = RandomPair(width, height, masks, width * 97 + octaves);
  WaterEnergyOptions options;
  options.detail_octaves = octaves;
  options.motion_weight = 0.7;
  options.detail_weight = 1.3;
  const double scale = 0.6;
  const Result want = CpuLoss(p, options, scale);
  const size_t n = p.rendered_a.size();
  const Result got =
      DeviceLoss(p, options, scale, Start(n, Largest(want.d_a), 1),
                 Start(n, Largest(want.d_b), 2), /*check_loss_alone=*/true);
  EXPECT_GT(want.terms.motion, 0);
  EXPECT_GT(want.terms.detail, 0);
  ExpectTwins(got, want);
}

INSTANTIATE_TEST_SUITE_P(
    Sizes, DeviceWaterEnergyLossTest,
    // Tiny (the emulation runs a thread per value): the coarse bands'
    // windows (radius 6, 12, 24) and blurs span the whole image.
    ::testing::Values(std::make_tuple(13, 9, false, 1),
                      std::make_tuple(11, 7, true, 1),
                      std::make_tuple(9, 7, true, 3),
                      std::make_tuple(5, 3, false, 2)),
    [](const auto& info) {
      return std::to_string(std::get<0>(info.param)) + "x" +
             std::to_string(std::get<1>(info.param)) +
             (std::get<2>(info.param) ? "_masks" : "_no_masks") +
             "_octaves" + std::to_string(std::get<3>(info.param));
    });

// A term weighted 0 is skipped on both sides (its unweighted value 0);
// both off, a loss of 0 and nothing added.
TEST(DeviceWaterEnergyLoss, TermsOff) {
  ES_REQUIRE_GPU("CUDA water energy loss");
  const Pair p = RandomPair(5, 3, true, 11);
  const size_t n = p.rendered_a.size();
  const std::vector<float> zeros(n, 0.0f);
  for (const auto& [motion, detail] : {std::make_pair(0.0, 1.0),
                                       std::make_pair(1.0, 0.0),
                                       std::make_pair(0.0, 0.0)}) {
    WaterEnergyOptions options;
    options.motion_weight = motion;
    options.detail_weight = detail;
    const Result want = CpuLoss(p, options, 1.0);
    const Result got = DeviceLoss(p, options, 1.0, zeros, zeros);
    if (motion == 0 && detail == 0) {
      EXPECT_EQ(got.loss, 0.0);
      for (double g : got.d_a) ASSERT_EQ(g, 0.0);
      for (double g : got.d_b) ASSERT_EQ(g, 0.0);
      continue;
    }
    EXPECT_EQ(got.terms.motion == 0, motion == 0);
    EXPECT_EQ(got.terms.detail == 0, detail == 0);
    ExpectTwins(got, want);
  }
}

// A flat render of frame A against textured input: its detail energies
// are 0, so its amplitudes sit on the eps floor (without it, 1 / (2 a)
// would be infinite and its product with a zero band NaN); loss and
// gradients finite and as the CPU's.
TEST(DeviceWaterEnergyLoss, FlatRender) {
  ES_REQUIRE_GPU("CUDA water energy loss");
  Pair p = RandomPair(9, 5, true, 5);
  std::fill(p.rendered_a.begin(), p.rendered_a.end(), 0.4f);
  WaterEnergyOptions options;
  options.detail_octaves = 2;
  const Result want = CpuLoss(p, options, 1.0);
  const size_t n = p.rendered_a.size();
  const Result got = DeviceLoss(p, options, 1.0, std::vector<float>(n, 0.0f),
                                std::vector<float>(n, 0.0f));
  EXPECT_TRUE(std::isfinite(got.loss));
  for (double g : got.d_a) ASSERT_TRUE(std::isfinite(g));
  for (double g : got.d_b) ASSERT_TRUE(std::isfinite(g));
  ExpectTwins(got, want);
}

// d loss / d rendered_a and _b at a border and an inner pixel against
// central differences of the device loss itself.
TEST(DeviceWaterEnergyLoss, GradientMatchesCentralDifferences) {
  ES_REQUIRE_GPU("CUDA water energy loss");
  const Pair p = RandomPair(7, 5, true, 9);
  WaterEnergyOptions options;
  options.detail_octaves = 2;
  const size_t n = p.rendered_a.size();
  const Result at = DeviceLoss(p, options, 1.0, std::vector<float>(n, 0.0f),
                               std::vector<float>(n, 0.0f));
  const float h = 1e-3f;
  // {frame, value}: a left border pixel's green in A, an inner pixel's
  // blue in B.
  const int picks[2][2] = {{0, 3 * (7 * 2) + 1}, {1, 3 * (7 * 2 + 3) + 2}};
  for (const auto& [frame, value] : picks) {
    double loss[2], step = 0;
    for (int side = 0; side < 2; ++side) {
      Pair moved = p;
      float& v =
          frame == 0 ? moved.rendered_a[value] : moved.rendered_b[value];
      const float base = v;
      v = side == 0 ? base + h : base - h;
      step += std::abs(static_cast<double>(v) - base);  // the float steps
      DeviceWaterEnergyLoss device(options);
      loss[side] = DevicePair(moved).Evaluate(moved, &device, 1.0, nullptr,
                                              nullptr, nullptr);
    }
    const double numeric = (loss[0] - loss[1]) / step;
    const double analytic = frame == 0 ? at.d_a[value] : at.d_b[value];
    EXPECT_NE(analytic, 0.0);
    EXPECT_NEAR(analytic, numeric, 1e-3 * std::abs(numeric) + 1e-7)
        << "frame " << frame << " value " << value;
  }
}

}  // namespace
}  // namespace cuda
}  // namespace es
