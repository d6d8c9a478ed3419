// The fast tiled rasterizer against the slow per-pixel reference twin
// (tests/reference_rasterizer.h): forward images, and backward gradients
// against the reference differentiated exactly with ceres::Jet.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "core/render/raster_constants.h"
#include "core/render/raster_project.h"
#include "core/render/rasterizer.h"
#include "core/render/tile_kernels.h"
#include "tests/reference_rasterizer.h"

namespace es {
namespace {

using reference::NeedleScene;
using reference::RandomScene;
using reference::StackedScene;
using reference::TestScene;

// Largest |a - b| over two arrays, and how many entries differ by more
// than `tol`.
int CountMismatches(const std::vector<double>& fast,
                    const std::vector<double>& ref, double tol,
                    double* max_diff) {
  EXPECT_EQ(fast.size(), ref.size());
  int bad = 0;
  for (size_t i = 0; i < std::min(fast.size(), ref.size()); ++i) {
    const double d = std::abs(fast[i] - ref[i]);
    *max_diff = std::max(*max_diff, d);
    if (d > tol) ++bad;
  }
  return bad;
}

// A scene of the forward tests (seed 0 and 1: random, 2: stacked splats)
// rendered by the rasterizer, in double or float, and by the reference.
struct ForwardRenders {
  TestScene scene;
  RenderResult fast;
  reference::Images<double> ref;
};
ForwardRenders RenderForward(unsigned seed, int degree, bool use_double) {
  ForwardRenders r;
  r.scene = seed == 2 ? StackedScene(seed, degree)
                      : RandomScene(seed + 10 * degree, 20, degree, 2);
  Rasterizer().Forward(r.scene.camera, r.scene.View(),
                       reference::TestRenderOptions(use_double), &r.fast);
  r.ref = reference::Render(r.scene.camera, r.scene.As<double>(),
                            reference::kTestBackground);
  return r;
}

class ReferenceForwardTest : public ::testing::TestWithParam<int> {};

TEST_P(ReferenceForwardTest, DoubleMatchesReference) {
  for (unsigned seed = 0; seed < 3; ++seed) {
    const auto [s, fast, ref] = RenderForward(seed, GetParam(), true);
    double max_diff = 0;
    EXPECT_EQ(CountMismatches(fast.rgb, ref.rgb, 1e-10, &max_diff), 0);
    EXPECT_EQ(CountMismatches(fast.alpha, ref.alpha, 1e-10, &max_diff), 0);
    EXPECT_EQ(CountMismatches(fast.depth, ref.depth, 1e-9, &max_diff), 0);
    EXPECT_EQ(CountMismatches(fast.extra, ref.extra, 1e-10, &max_diff), 0);
    double peak = 0;
    for (double a : ref.alpha) peak = std::max(peak, a);
    EXPECT_GT(peak, 0.5) << "scene should show something";
  }
}

TEST_P(ReferenceForwardTest, FloatMatchesReference) {
  for (unsigned seed = 0; seed < 3; ++seed) {
    const auto [s, fast, ref] = RenderForward(seed, GetParam(), false);
    // Float may flip a decision exactly at a cut-off (alpha = 1/255,
    // T = 1e-4) in a rare pixel; everywhere else it agrees to float
    // rounding.
    double max_diff = 0;
    const int pixels = s.camera.width * s.camera.height;
    EXPECT_LE(CountMismatches(fast.rgb, ref.rgb, 1e-5, &max_diff),
              3 * pixels / 200);
    EXPECT_LE(CountMismatches(fast.alpha, ref.alpha, 1e-5, &max_diff),
              pixels / 200);
    EXPECT_LT(max_diff, 0.05);
  }
}

INSTANTIATE_TEST_SUITE_P(ShDegrees, ReferenceForwardTest,
                         ::testing::Values(0, 1, 2, 3));

// Exact gradients of loss = sum weights * outputs of the reference, one
// Gaussian at a time (its parameters are the Jet's infinitesimal parts).
constexpr int kJetSize = 64;
using Jet = ceres::Jet<double, kJetSize>;

struct Weights {
  std::vector<double> rgb, alpha, depth, extra;
};

// The rasterizer's gradients of the last Forward for loss weights w.
SplatGradients BackwardWith(Rasterizer* r, const Weights& w) {
  SplatGradients g;
  r->Backward({w.rgb.data(), w.alpha.data(), w.depth.data(), w.extra.data()},
              &g);
  return g;
}

Weights RandomWeights(const TestScene& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1, 1);
  const int pixels = s.camera.width * s.camera.height;
  Weights w;
  for (int i = 0; i < 3 * pixels; ++i) w.rgb.push_back(uni(rng));
  for (int i = 0; i < pixels; ++i) w.alpha.push_back(uni(rng));
  for (int i = 0; i < pixels; ++i) w.depth.push_back(0.2 * uni(rng));
  for (int i = 0; i < pixels * s.num_extra; ++i) w.extra.push_back(uni(rng));
  return w;
}

SplatGradients ReferenceGradients(const TestScene& s, const Weights& w) {
  SplatGradients g;
  g.Resize(s.count, s.sh_degree, s.num_extra);
  const int sh_size = 3 * NumShCoeffs(s.sh_degree);
  EXPECT_LE(11 + sh_size + s.num_extra, kJetSize);
  for (int n = 0; n < s.count; ++n) {
    reference::Splats<Jet> js = s.As<Jet>();
    // Slots: means 0-2, log-scales 3-5, quats 6-9, opacity 10, SH, extras.
    for (int i = 0; i < 3; ++i) js.means[3 * n + i].v[i] = 1;
    for (int i = 0; i < 3; ++i) js.log_scales[3 * n + i].v[3 + i] = 1;
    for (int i = 0; i < 4; ++i) js.quats[4 * n + i].v[6 + i] = 1;
    js.opacity_logits[n].v[10] = 1;
    for (int i = 0; i < sh_size; ++i) js.sh[sh_size * n + i].v[11 + i] = 1;
    for (int e = 0; e < s.num_extra; ++e) {
      js.extra[s.num_extra * n + e].v[11 + sh_size + e] = 1;
    }
    const auto img =
        reference::Render(s.camera, js, reference::kTestBackground);
    Jet loss(0);
    for (size_t i = 0; i < w.rgb.size(); ++i) loss += w.rgb[i] * img.rgb[i];
    for (size_t i = 0; i < w.alpha.size(); ++i) {
      loss += w.alpha[i] * img.alpha[i];
      loss += w.depth[i] * img.depth[i];
    }
    for (size_t i = 0; i < w.extra.size(); ++i) {
      loss += w.extra[i] * img.extra[i];
    }
    for (int i = 0; i < 3; ++i) g.means[3 * n + i] = loss.v[i];
    for (int i = 0; i < 3; ++i) g.log_scales[3 * n + i] = loss.v[3 + i];
    for (int i = 0; i < 4; ++i) g.quats[4 * n + i] = loss.v[6 + i];
    g.opacity_logits[n] = loss.v[10];
    for (int i = 0; i < sh_size; ++i) g.sh[sh_size * n + i] = loss.v[11 + i];
    for (int e = 0; e < s.num_extra; ++e) {
      g.extra[s.num_extra * n + e] = loss.v[11 + sh_size + e];
    }
  }
  return g;
}

// Entries of `fast` within rel_tol of `ref`, relative to the largest
// reference entry of that parameter type.
void ExpectGradientsClose(const std::vector<double>& fast,
                          const std::vector<double>& ref, double rel_tol,
                          const std::string& name) {
  ASSERT_EQ(fast.size(), ref.size()) << name;
  double scale = 0;
  for (double v : ref) scale = std::max(scale, std::abs(v));
  for (size_t i = 0; i < ref.size(); ++i) {
    EXPECT_NEAR(fast[i], ref[i], rel_tol * scale) << name << "[" << i << "]";
  }
}

// Every parameter type's gradient within rel_tol of the reference's.
void ExpectAllGradientsClose(const SplatGradients& fast,
                             const SplatGradients& ref, double rel_tol) {
  ExpectGradientsClose(fast.means, ref.means, rel_tol, "means");
  ExpectGradientsClose(fast.log_scales, ref.log_scales, rel_tol,
                       "log_scales");
  ExpectGradientsClose(fast.quats, ref.quats, rel_tol, "quats");
  ExpectGradientsClose(fast.opacity_logits, ref.opacity_logits, rel_tol,
                       "opacity_logits");
  ExpectGradientsClose(fast.sh, ref.sh, rel_tol, "sh");
  ExpectGradientsClose(fast.extra, ref.extra, rel_tol, "extra");
}

class ReferenceBackwardTest : public ::testing::TestWithParam<int> {};

TEST_P(ReferenceBackwardTest, MatchesReferenceJetGradients) {
  const int degree = GetParam();
  const TestScene s = degree == 2 ? StackedScene(4, degree)
                                  : RandomScene(40 + degree, 10, degree, 1,
                                                32, 24);
  const Weights w = RandomWeights(s, 9);
  const SplatGradients ref = ReferenceGradients(s, w);
  for (bool use_double : {true, false}) {
    SCOPED_TRACE(use_double ? "double" : "float");
    Rasterizer r;
    RenderResult out;
    r.Forward(s.camera, s.View(), reference::TestRenderOptions(use_double),
              &out);
    const SplatGradients g = BackwardWith(&r, w);
    // Float: per-pixel float rounding, and T recovered by division.
    const double tol = use_double ? 1e-9 : 2e-3;
    ExpectAllGradientsClose(g, ref, tol);
  }
}

INSTANTIATE_TEST_SUITE_P(ShDegrees, ReferenceBackwardTest,
                         ::testing::Values(0, 1, 2, 3));

// Image gradients that are zero on whole tiles (a loss that reads some
// pixels only): the tiles skipped, the others (each with one kind of
// gradient, one of them at the image's ragged right edge) still match the
// reference.
TEST(ReferenceBackwardTest, TilesWithoutGradientsAreSkippedExactly) {
  const TestScene s = RandomScene(41, 12, 1, 1, 40, 24);  // 3 x 2 tiles
  const int w = s.camera.width, pixels = w * s.camera.height;
  Weights weights = RandomWeights(s, 10);
  Weights sparse;
  sparse.rgb.assign(3 * pixels, 0.0);
  sparse.alpha.assign(pixels, 0.0);
  sparse.depth.assign(pixels, 0.0);
  sparse.extra.assign(pixels * s.num_extra, 0.0);
  for (int y = 0; y < 16; ++y)  // tile (1, 0): colour
    for (int x = 16; x < 32; ++x)
      for (int c = 0; c < 3; ++c)
        sparse.rgb[3 * (y * w + x) + c] = weights.rgb[3 * (y * w + x) + c];
  sparse.alpha[20 * w + 37] = weights.alpha[20 * w + 37];  // tile (2, 1)
  sparse.extra[s.num_extra * (17 * w + 3)] = 1.0;           // tile (0, 1)
  const SplatGradients ref = ReferenceGradients(s, sparse);
  Rasterizer r;
  RenderResult out;
  r.Forward(s.camera, s.View(), reference::TestRenderOptions(true), &out);
  ExpectAllGradientsClose(BackwardWith(&r, sparse), ref, 1e-9);
}

// Rows of pixel boxes within tiles where no pixel reaches kMinAlpha (the
// Gaussian's sigma above log(opacity / kMinAlpha) at every pixel), in
// double from the projection: what the scene gives the row skip to do.
int RowsMissingTheEllipse(const TestScene& s) {
  const ProjectionCamera cam(s.camera);
  const SplatView view = s.View();
  int rows = 0;
  for (int n = 0; n < s.count; ++n) {
    ProjectedSplat p;
    if (!ProjectSplat(cam, view, n, &p)) continue;
    const double level = std::log(p.opacity / kMinAlpha);
    for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
      for (int tx = p.tile_x0; tx < p.tile_x1; ++tx) {
        const int x0 = std::max(p.px0, tx * kTileSize);
        const int x1 = std::min(p.px1, (tx + 1) * kTileSize);
        const int y0 = std::max(p.py0, ty * kTileSize);
        const int y1 = std::min(p.py1, (ty + 1) * kTileSize);
        for (int y = y0; y < y1; ++y) {
          bool reached = false;
          for (int x = x0; x < x1; ++x) {
            const double dx = x + 0.5 - p.mean2d[0];
            const double dy = y + 0.5 - p.mean2d[1];
            const double sigma =
                0.5 * (p.conic[0] * dx * dx + p.conic[2] * dy * dy) +
                p.conic[1] * dx * dy;
            reached |= sigma <= level;
          }
          rows += x1 > x0 && !reached;
        }
      }
    }
  }
  return rows;
}

TEST(RowSkipTest, NeedlesAndTileCornersMatchReference) {
  const TestScene s = NeedleScene();
  EXPECT_GT(RowsMissingTheEllipse(s), 150);
  const auto ref =
      reference::Render(s.camera, s.As<double>(), reference::kTestBackground);
  double peak = 0;
  for (double a : ref.alpha) peak = std::max(peak, a);
  EXPECT_GT(peak, 0.5);  // the needles render
  const Weights w = RandomWeights(s, 5);
  const SplatGradients ref_grads = ReferenceGradients(s, w);
  for (SimdLevel level :
       {SimdLevel::kSse2, SimdLevel::kAvx2, SimdLevel::kAvx512}) {
    if (!SimdLevelSupported(level)) continue;
    for (bool use_double : {true, false}) {
      SCOPED_TRACE(std::string(SimdLevelName(level)) +
                   (use_double ? " double" : " float"));
      RenderOptions o = reference::TestRenderOptions(use_double);
      o.simd = level;
      Rasterizer r;
      RenderResult out;
      r.Forward(s.camera, s.View(), o, &out);
      // A row wrongly skipped loses at least kMinAlpha of a colour.
      const double tol = use_double ? 1e-10 : 2e-5;
      double max_diff = 0;
      EXPECT_EQ(CountMismatches(out.rgb, ref.rgb, tol, &max_diff), 0);
      EXPECT_EQ(CountMismatches(out.alpha, ref.alpha, tol, &max_diff), 0);
      EXPECT_EQ(CountMismatches(out.extra, ref.extra, tol, &max_diff), 0);
      const SplatGradients g = BackwardWith(&r, w);
      const double gtol = use_double ? 1e-9 : 2e-3;
      ExpectAllGradientsClose(g, ref_grads, gtol);
    }
  }
}

}  // namespace
}  // namespace es
