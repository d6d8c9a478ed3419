// The tile kernels compiled for each instruction set (core/render/
// tile_kernels.h) against the SSE2 baseline and the per-pixel reference:
// every level the CPU supports must render the same images and gradients
// within float tolerance (double: to rounding).

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/render/rasterizer.h"
#include "tests/max_abs_diff.h"
#include "tests/per_simd_level_test.h"
#include "tests/reference_rasterizer.h"

namespace es {
namespace {

using reference::RandomScene;
using reference::TestScene;

struct Pass {
  RenderResult image;
  SplatGradients grads;
  std::vector<double> mean2d;
};

// Forward, then backward with fixed pseudo-random image gradients on every
// output (rgb, alpha, depth, extras).
Pass RenderBoth(const TestScene& s, SimdLevel level, bool use_double) {
  RenderOptions o;
  o.simd = level;
  o.use_double = use_double;
  o.background = Eigen::Vector3d(0.2, 0.5, 0.7);
  Rasterizer r;
  Pass p;
  r.Forward(s.camera, s.View(), o, &p.image);
  const size_t pixels =
      static_cast<size_t>(s.camera.width) * s.camera.height;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> d_rgb(3 * pixels), d_alpha(pixels), d_depth(pixels),
      d_extra(pixels * s.num_extra);
  for (auto* v : {&d_rgb, &d_alpha, &d_depth, &d_extra})
    for (double& x : *v) x = uni(rng);
  r.Backward({d_rgb.data(), d_alpha.data(), d_depth.data(), d_extra.data()},
             &p.grads);
  r.Mean2dGradients(&p.mean2d);
  return p;
}

// max |a - b| / (1 + max |b|) over two arrays of equal size.
double RelativeDiff(const std::vector<double>& a,
                    const std::vector<double>& b) {
  const AbsDiff d = MaxAbsDiff(a, b);
  return d.diff / (1 + d.scale);
}

double WorstDiff(const Pass& a, const Pass& b) {
  double worst = 0;
  for (auto [x, y] :
       {std::pair{&a.image.rgb, &b.image.rgb},
        {&a.image.alpha, &b.image.alpha}, {&a.image.depth, &b.image.depth},
        {&a.image.extra, &b.image.extra}, {&a.grads.means, &b.grads.means},
        {&a.grads.log_scales, &b.grads.log_scales},
        {&a.grads.quats, &b.grads.quats},
        {&a.grads.opacity_logits, &b.grads.opacity_logits},
        {&a.grads.sh, &b.grads.sh}, {&a.grads.extra, &b.grads.extra},
        {&a.mean2d, &b.mean2d}})
    worst = std::max(worst, RelativeDiff(*x, *y));
  return worst;
}

// Big enough for the parallel tile loop (> 256 binned entries), several
// tiles, boxes cut by tile borders, two extra channels.
TestScene Scene(unsigned seed) {
  return RandomScene(seed, 400, 3, 2, 83, 61);
}

class SimdLevelTest : public PerSimdLevelTest {};

TEST_P(SimdLevelTest, FloatMatchesSse2WithinFloatTolerance) {
  for (unsigned seed = 0; seed < 3; ++seed) {
    const TestScene s = Scene(seed);
    const Pass base = RenderBoth(s, SimdLevel::kSse2, false);
    const Pass mine = RenderBoth(s, GetParam(), false);
    EXPECT_LT(WorstDiff(mine, base), 1e-4) << "seed " << seed;
    // The scene must render something, or the comparison proves nothing.
    double peak = 0;
    for (double a : base.image.alpha) peak = std::max(peak, a);
    EXPECT_GT(peak, 0.5);
  }
}

TEST_P(SimdLevelTest, DoubleMatchesSse2ToRounding) {
  const TestScene s = Scene(7);
  EXPECT_LT(WorstDiff(RenderBoth(s, GetParam(), true),
                      RenderBoth(s, SimdLevel::kSse2, true)),
            1e-10);
}

TEST_P(SimdLevelTest, DoubleMatchesPerPixelReference) {
  const TestScene s = RandomScene(11, 30, 2, 1);
  const Pass p = RenderBoth(s, GetParam(), true);
  const Eigen::Vector3d bg(0.2, 0.5, 0.7);
  const auto ref = reference::Render(s.camera, s.As<double>(), bg);
  EXPECT_LT(RelativeDiff(p.image.rgb, ref.rgb), 1e-10);
  EXPECT_LT(RelativeDiff(p.image.alpha, ref.alpha), 1e-10);
  EXPECT_LT(RelativeDiff(p.image.extra, ref.extra), 1e-10);
}

// Small footprints, many in front of each other: with full rows
// (AVX2 / AVX-512) the boxes of at most half a tile row run on a half-row
// window placed over them, at tile and image edges too, and pixels stop.
// They must give what the span-only SSE2 kernel gives.
TestScene NarrowScene(unsigned seed) {
  TestScene s;
  s.camera = reference::TestCamera(83, 61);
  s.sh_degree = 1;
  s.num_extra = 1;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double f = s.camera.fx;
  for (int i = 0; i < 1500; ++i) {
    const double z = 2 + 3 * uni(rng);
    // Sigma 0.3..1.3 px: boxes of 3..11 pixels, most within 8.
    const double px = 0.3 + uni(rng);
    const Eigen::Vector3d scale(px * z / f * (0.6 + 0.6 * uni(rng)),
                                px * z / f * (0.6 + 0.6 * uni(rng)),
                                px * z / f);
    const Eigen::Vector4d q(uni(rng) - 0.5, uni(rng) - 0.5, uni(rng) - 0.5,
                            uni(rng) - 0.5);
    // Clustered on a few spots so pixels reach the transmittance limit.
    const double u = i % 3 == 0 ? 40 + 6 * (uni(rng) - 0.5)
                                : -3 + 89 * uni(rng);
    const double v = i % 3 == 0 ? 30 + 6 * (uni(rng) - 0.5)
                                : -3 + 67 * uni(rng);
    s.Add(s.camera.Unproject(u, v, z), scale, q, -1 + 6 * uni(rng));
  }
  const int k_count = NumShCoeffs(s.sh_degree);
  for (double& c : s.sh) c = (uni(rng) - 0.5) * 2;
  for (int n = 0; n < s.count; ++n) s.sh[3 * k_count * n] += 1;  // DC red
  for (double& e : s.extra) e = uni(rng);
  return s;
}

TEST_P(SimdLevelTest, NarrowFootprintsMatchSse2WithinFloatTolerance) {
  const TestScene s = NarrowScene(5);
  // Most boxes fit a half row (radius 3 px: a box of at most ~8 pixels).
  Rasterizer r;
  RenderResult image;
  r.Forward(s.camera, s.View(), RenderOptions(), &image);
  std::vector<int> radii;
  r.Radii(&radii);
  int small = 0;
  for (int radius : radii) small += radius > 0 && radius <= 3;
  EXPECT_GT(small, s.count / 2);
  double peak = 0;
  for (double a : image.alpha) peak = std::max(peak, a);
  EXPECT_GT(peak, 0.999);  // some pixels stop
  for (bool use_double : {false, true}) {
    EXPECT_LT(WorstDiff(RenderBoth(s, GetParam(), use_double),
                        RenderBoth(s, SimdLevel::kSse2, use_double)),
              use_double ? 1e-10 : 1e-4)
        << (use_double ? "double" : "float");
  }
}

INSTANTIATE_TEST_SUITE_P(Levels, SimdLevelTest, AllSimdLevels(),
                         SimdLevelTestName);

TEST(SimdLevelTest, AutoResolvesToASupportedLevel) {
  const SimdLevel best = BestSimdLevel();
  EXPECT_NE(best, SimdLevel::kAuto);
  EXPECT_TRUE(SimdLevelSupported(best));
  EXPECT_EQ(ResolveSimdLevel(SimdLevel::kAuto), best);
  EXPECT_TRUE(SimdLevelSupported(SimdLevel::kSse2));
}

}  // namespace
}  // namespace es
