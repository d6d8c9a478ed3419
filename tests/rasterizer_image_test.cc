// Forward images of the fast rasterizer against values derived by hand, and
// robustness on degenerate input.

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "core/render/rasterizer.h"
#include "core/render/render_maps.h"
#include "tests/centered_camera.h"
#include "tests/reference_rasterizer.h"

namespace es {
namespace {

using reference::TestScene;

// Identity pose looking down +z; (0, 0, z) projects to (cx, cy).
double DcFor(double color) { return (color - 0.5) / kShC0; }

class RasterizerPrecisionTest : public ::testing::TestWithParam<bool> {
 protected:
  RenderOptions Options() const {
    RenderOptions o;
    o.use_double = GetParam();
    return o;
  }
  double Tolerance() const { return GetParam() ? 1e-12 : 2e-6; }
};

TEST_P(RasterizerPrecisionTest, IsotropicGaussianMatchesClosedForm) {
  TestScene s;
  s.camera = CenteredCamera(48, 40, 40);
  const double scale = 0.25, z = 5, opacity = 0.8;
  // A mean off the pixel grid: (0.3, -0.2, 5) -> u = 26.4, v = 18.4.
  s.Add(Eigen::Vector3d(0.3, -0.2, z), Eigen::Vector3d::Constant(scale),
        Eigen::Vector4d(1, 0, 0, 0), Logit(opacity));
  s.sh = {DcFor(0.9), DcFor(0.4), DcFor(0.1)};
  RenderOptions options = Options();
  options.background = Eigen::Vector3d(0.0, 0.0, 1.0);
  Rasterizer r;
  RenderResult out;
  r.Forward(s.camera, s.View(), options, &out);
  ASSERT_EQ(r.num_visible(), 1);

  // Off the optical axis the perspective Jacobian J = [f/z 0 -f x/z^2;
  // 0 f/z -f y/z^2] makes the isotropic 3D covariance s^2 I anisotropic:
  // cov2 = s^2 J J^T + 0.3 I.
  const double f = 40, x = 0.3, y = -0.2;
  const double k = scale * scale * f * f / (z * z);
  const double a = k * (1 + x * x / (z * z)) + 0.3;
  const double b = k * x * y / (z * z);
  const double c = k * (1 + y * y / (z * z)) + 0.3;
  const double det = a * c - b * b;
  const double u = f * x / z + 24, v = f * y / z + 20;
  for (int i = 12; i < 26; i += 3) {
    for (int j = 20; j < 33; j += 2) {
      const double dx = j + 0.5 - u, dy = i + 0.5 - v;
      const double sigma = 0.5 * (c * dx * dx - 2 * b * dx * dy + a * dy * dy)
                           / det;
      double alpha = opacity * std::exp(-sigma);
      if (alpha < 1.0 / 255) alpha = 0;
      const int p = i * 48 + j;
      EXPECT_NEAR(out.alpha[p], alpha, Tolerance()) << j << "," << i;
      EXPECT_NEAR(out.rgb[3 * p + 0], 0.9 * alpha, Tolerance());
      EXPECT_NEAR(out.rgb[3 * p + 1], 0.4 * alpha, Tolerance());
      EXPECT_NEAR(out.rgb[3 * p + 2], 0.1 * alpha + (1 - alpha), Tolerance());
      EXPECT_NEAR(out.depth[p], z * alpha, 5 * Tolerance());
    }
  }
  // The peak is at the pixel whose center is nearest the mean, (26, 18).
  int best = 0;
  for (int p = 0; p < 48 * 40; ++p) {
    if (out.alpha[p] > out.alpha[best]) best = p;
  }
  EXPECT_EQ(best % 48, 26);
  EXPECT_EQ(best / 48, 18);
  // ExpectedDepth divides the alpha out.
  EXPECT_NEAR(ExpectedDepth(out)[best], z, 1e-5);
}

TEST_P(RasterizerPrecisionTest, CompositesFrontToBackByDepth) {
  TestScene s;
  s.camera = CenteredCamera(32, 32, 30);
  // Listed back first: the sort must put the nearer (red) one in front.
  s.Add(Eigen::Vector3d(0, 0, 6), Eigen::Vector3d::Constant(1.0),
        Eigen::Vector4d(1, 0, 0, 0), Logit(0.7));
  s.Add(Eigen::Vector3d(0, 0, 3), Eigen::Vector3d::Constant(0.5),
        Eigen::Vector4d(0.5, 0.5, 0.5, 0.5), Logit(0.6));
  s.sh = {DcFor(0), DcFor(1), DcFor(0), DcFor(1), DcFor(0), DcFor(0)};
  RenderOptions options = Options();
  options.background = Eigen::Vector3d(0.1, 0.2, 0.3);
  Rasterizer r;
  RenderResult out;
  r.Forward(s.camera, s.View(), options, &out);
  // Pixel (15, 15) is 0.5 px from both means in x and y.
  const int p = 15 * 32 + 15;
  auto alpha_at = [](double sigma_px, double o) {
    const double var = sigma_px * sigma_px + 0.3;
    return o * std::exp(-0.5 * (0.25 + 0.25) / var);
  };
  const double a_red = alpha_at(0.5 * 30 / 3, 0.6);
  const double a_green = alpha_at(1.0 * 30 / 6, 0.7);
  const double t1 = 1 - a_red, t2 = t1 * (1 - a_green);
  EXPECT_NEAR(out.rgb[3 * p + 0], a_red + 0.1 * t2, 10 * Tolerance());
  EXPECT_NEAR(out.rgb[3 * p + 1], t1 * a_green + 0.2 * t2, 10 * Tolerance());
  EXPECT_NEAR(out.rgb[3 * p + 2], 0.3 * t2, 10 * Tolerance());
  EXPECT_NEAR(out.alpha[p], 1 - t2, 10 * Tolerance());
  EXPECT_NEAR(out.depth[p], 3 * a_red + 6 * t1 * a_green, 50 * Tolerance());
}

TEST_P(RasterizerPrecisionTest, StopsBeforeTransmittanceFallsBelowLimit) {
  TestScene s;
  s.camera = CenteredCamera(16, 16, 20);
  // Ten wide layers of alpha ~0.95 at the center: T = 0.05, 2.5e-3,
  // 1.25e-4, then 6.25e-6 < 1e-4, so 3DGS stops before the fourth layer.
  const double opacity = 0.95;
  for (int k = 0; k < 10; ++k) {
    s.Add(Eigen::Vector3d(0, 0, 2 + k), Eigen::Vector3d::Constant(5.0),
          Eigen::Vector4d(1, 0, 0, 0), Logit(opacity));
  }
  s.sh.assign(s.sh.size(), DcFor(1.0));
  Rasterizer r;
  RenderResult out;
  r.Forward(s.camera, s.View(), Options(), &out);
  // Pixel (8, 8) is 0.5 px from the means in x and y.
  double t = 1, depth = 0;
  for (int k = 0; k < 3; ++k) {
    const double sigma_px = 5.0 * 20 / (2 + k);
    const double alpha =
        opacity * std::exp(-0.25 / (sigma_px * sigma_px + 0.3));
    depth += (2 + k) * alpha * t;
    t *= 1 - alpha;
  }
  const int p = 8 * 16 + 8;
  EXPECT_NEAR(1 - out.alpha[p], t, 1e-7);
  EXPECT_NEAR(out.depth[p], depth, 1e-5);
  EXPECT_NEAR(out.rgb[3 * p], 1 - t, 1e-6);
}

TEST_P(RasterizerPrecisionTest, ReportsRadiiAndViewSpaceGradients) {
  TestScene s;
  s.camera = CenteredCamera(48, 40, 40);
  // On the optical axis an isotropic Gaussian's footprint does not change
  // to first order when it moves sideways, so d loss / d x = fx / z *
  // d loss / d u exactly (SH degree 0: no view-dependent color).
  s.Add(Eigen::Vector3d(0, 0, 4), Eigen::Vector3d::Constant(0.3),
        Eigen::Vector4d(1, 0, 0, 0), 1.0);
  s.Add(Eigen::Vector3d(0, 0, -4), Eigen::Vector3d::Constant(0.3),
        Eigen::Vector4d(1, 0, 0, 0), 1.0);  // behind: culled
  s.sh = {DcFor(0.8), DcFor(0.3), DcFor(0.5), 0, 0, 0};
  Rasterizer r;
  RenderResult out;
  r.Forward(s.camera, s.View(), Options(), &out);
  std::vector<int> radii;
  r.Radii(&radii);
  // cov2 = (40 * 0.3 / 4)^2 + 0.3 = 9.3 on both axes: r = ceil(3 sqrt(9.3)).
  EXPECT_EQ(radii, std::vector<int>({10, 0}));
  // Red rewarded right of the mean, green below it.
  std::vector<double> d_rgb(out.rgb.size(), 0.0);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 48; ++j) {
      d_rgb[3 * (i * 48 + j)] = j >= 24 ? 1.0 : 0.0;
      d_rgb[3 * (i * 48 + j) + 1] = i >= 20 ? 1.0 : 0.0;
    }
  }
  SplatGradients g;
  r.Backward({d_rgb.data(), nullptr, nullptr, nullptr}, &g);
  std::vector<double> g2d;
  r.Mean2dGradients(&g2d);
  ASSERT_EQ(g2d.size(), 4u);
  EXPECT_GT(g2d[0], 1e-2);  // moving right increases the loss
  EXPECT_GT(g2d[1], 1e-2);  // moving down (y down) too
  EXPECT_NEAR(g.means[0], 40.0 / 4 * g2d[0], 1e-5 * std::abs(g.means[0]));
  EXPECT_NEAR(g.means[1], 40.0 / 4 * g2d[1], 1e-5 * std::abs(g.means[1]));
  EXPECT_EQ(g2d[2], 0.0);
  EXPECT_EQ(g2d[3], 0.0);
}

INSTANTIATE_TEST_SUITE_P(FloatAndDouble, RasterizerPrecisionTest,
                         ::testing::Values(false, true));

bool AllFinite(const std::vector<double>& v) {
  for (double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

TEST(RasterizerHardCases, NeverCrashesOrProducesNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (bool use_double : {false, true}) {
    TestScene s;
    s.camera = CenteredCamera(40, 32, 35);
    s.num_extra = 1;
    const Eigen::Vector4d id(1, 0, 0, 0);
    s.Add({0, 0, -2}, {0.5, 0.5, 0.5}, id, 3);       // behind the camera
    s.Add({0.1, 0, 0}, {0.5, 0.5, 0.5}, id, 3);      // at z = 0
    s.Add({0, 0, 0.01}, {0.5, 0.5, 0.5}, id, 3);     // on the near plane
    s.Add({0, 0, 0.0101}, {1e-3, 1e-3, 1e-3}, id, 3);  // just past it
    s.Add({0.3, 0.2, 4}, {1e6, 1e6, 1e6}, id, 0);     // huge
    s.Add({0.1, 0.1, 3}, {1e-8, 1e-8, 1e-8}, id, 5);  // tiny
    s.Add({-0.2, 0.1, 3}, {1e-8, 1e-8, 1.0}, id, 5);  // degenerate needle
    s.Add({0.2, -0.1, 2}, {0.1, 0.1, 0.1}, {0, 0, 0, 0}, 2);  // zero quat
    s.Add({nan, 0, 3}, {0.1, 0.1, 0.1}, id, 2);       // NaN mean
    s.Add({0, 0, 3}, {0.1, 0.1, 0.1}, id, nan);       // NaN opacity
    s.Add({0, 0, 5}, {0.1, 0.1, 0.1}, id, 2);
    s.log_scales[3 * 9] = inf;                       // exp(inf) scale
    s.log_scales[3 * 10 + 1] = 800;                  // overflows exp
    for (double& e : s.extra) e = 0.5;
    for (size_t i = 0; i < s.sh.size(); i += 3) s.sh[i] = 1.0;
    RenderOptions options;
    options.use_double = use_double;
    options.background = Eigen::Vector3d(0.5, 0.5, 0.5);
    Rasterizer r;
    RenderResult out;
    r.Forward(s.camera, s.View(), options, &out);
    EXPECT_TRUE(AllFinite(out.rgb));
    EXPECT_TRUE(AllFinite(out.alpha));
    EXPECT_TRUE(AllFinite(out.depth));
    EXPECT_TRUE(AllFinite(out.extra));
    // Only the huge, tiny, needle and just-past-near ones can show.
    EXPECT_LE(r.num_visible(), 4);
    EXPECT_GE(r.num_visible(), 1);
    std::vector<double> ones_rgb(out.rgb.size(), 1.0);
    std::vector<double> ones(out.alpha.size(), 1.0);
    SplatGradients g;
    r.Backward({ones_rgb.data(), ones.data(), ones.data(), ones.data()}, &g);
    EXPECT_TRUE(AllFinite(g.means));
    EXPECT_TRUE(AllFinite(g.log_scales));
    EXPECT_TRUE(AllFinite(g.quats));
    EXPECT_TRUE(AllFinite(g.opacity_logits));
    EXPECT_TRUE(AllFinite(g.sh));
    EXPECT_TRUE(AllFinite(g.extra));
  }
}

TEST(RasterizerHardCases, CulledGaussiansDoNotChangeTheImage) {
  TestScene s = reference::RandomScene(11, 10, 2, 1);
  Rasterizer r;
  RenderResult before, after;
  r.Forward(s.camera, s.View(), RenderOptions(), &before);
  const int visible = r.num_visible();
  const Eigen::Vector3d center = s.camera.Center();
  const Eigen::Vector3d behind =
      center - s.camera.R().transpose() * Eigen::Vector3d(0, 0, 1);
  s.Add(s.camera.R() * (behind - center), {1, 1, 1}, {1, 0, 0, 0}, 3);
  s.Add({0, 0, 0.005}, {1, 1, 1}, {1, 0, 0, 0}, 3);
  s.Add({0, 0, 4}, {1, 1, 1}, {1, 0, 0, 0}, -8);  // opacity < 1/255
  s.Add({100, 0, 4}, {0.1, 0.1, 0.1}, {1, 0, 0, 0}, 3);  // off-screen
  r.Forward(s.camera, s.View(), RenderOptions(), &after);
  EXPECT_EQ(r.num_visible(), visible);
  EXPECT_EQ(before.rgb, after.rgb);
  EXPECT_EQ(before.alpha, after.alpha);
}

// Images and gradients are the same, to the bit, on any number of threads:
// binning keeps every tile's list in depth order, and each Gaussian's tile
// shares of the gradient are summed in a fixed order (no atomics).
TEST(RasterizerThreads, ImagesAndGradientsDoNotDependOnThreadCount) {
  // Enough Gaussians for the parallel binning.
  const TestScene s = reference::RandomScene(21, 20000, 3, 1, 160, 120);
  std::vector<double> d_rgb(3 * 160 * 120), d_other(160 * 120);
  for (size_t i = 0; i < d_rgb.size(); ++i) d_rgb[i] = std::sin(0.37 * i);
  for (size_t i = 0; i < d_other.size(); ++i) d_other[i] = std::cos(0.11 * i);
  const RenderGradients image_grads{d_rgb.data(), d_other.data(),
                                    d_other.data(), d_other.data()};
  Rasterizer r;
  RenderResult one;
  SplatGradients one_grads;
  omp_set_num_threads(1);
  r.Forward(s.camera, s.View(), RenderOptions(), &one);
  r.Backward(image_grads, &one_grads);
  // Binning splits the depth order into one run per thread.
  for (int threads : {2, 3}) {
    RenderResult many;
    SplatGradients many_grads;
    omp_set_num_threads(threads);
    r.Forward(s.camera, s.View(), RenderOptions(), &many);
    r.Backward(image_grads, &many_grads);
    EXPECT_EQ(one.rgb, many.rgb) << threads << " threads";
    EXPECT_EQ(one.depth, many.depth) << threads << " threads";
    EXPECT_EQ(one.extra, many.extra) << threads << " threads";
    EXPECT_EQ(one_grads.means, many_grads.means) << threads << " threads";
    EXPECT_EQ(one_grads.quats, many_grads.quats) << threads << " threads";
    EXPECT_EQ(one_grads.sh, many_grads.sh) << threads << " threads";
    EXPECT_EQ(one_grads.extra, many_grads.extra) << threads << " threads";
  }
  omp_set_num_threads(2);
}

// Backward overwrites the whole gradient, whatever the buffer held: culled
// Gaussians (behind the camera, transparent, off-screen) get zeros, the
// kept ones what a fresh buffer gets, with and without the parallel pass.
TEST(RasterizerHardCases, BackwardOverwritesStaleGradientsWithCulledZeros) {
  for (int n : {10, 4000}) {
    TestScene s = reference::RandomScene(13, n, 2, 1);
    const Eigen::Vector3d center = s.camera.Center();
    const Eigen::Vector3d behind =
        center - s.camera.R().transpose() * Eigen::Vector3d(0, 0, 1);
    s.Add(s.camera.R() * (behind - center), {1, 1, 1}, {1, 0, 0, 0}, 3);
    s.Add({0, 0, 4}, {1, 1, 1}, {1, 0, 0, 0}, -8);  // opacity < 1/255
    s.Add({100, 0, 4}, {0.1, 0.1, 0.1}, {1, 0, 0, 0}, 3);  // off-screen
    const int count = n + 3;
    Rasterizer r;
    RenderResult out;
    r.Forward(s.camera, s.View(), RenderOptions(), &out);
    std::vector<double> ones_rgb(out.rgb.size(), 1.0);
    std::vector<double> ones(out.alpha.size(), 1.0);
    const RenderGradients image_grads{ones_rgb.data(), ones.data(),
                                      ones.data(), ones.data()};
    SplatGradients fresh, stale;
    r.Backward(image_grads, &fresh);
    stale.Resize(count, s.sh_degree, s.num_extra);
    for (auto* v : {&stale.means, &stale.log_scales, &stale.quats,
                    &stale.opacity_logits, &stale.sh, &stale.extra})
      std::fill(v->begin(), v->end(), 7.0);
    r.Backward(image_grads, &stale);
    EXPECT_EQ(fresh.means, stale.means);
    EXPECT_EQ(fresh.log_scales, stale.log_scales);
    EXPECT_EQ(fresh.quats, stale.quats);
    EXPECT_EQ(fresh.opacity_logits, stale.opacity_logits);
    EXPECT_EQ(fresh.sh, stale.sh);
    EXPECT_EQ(fresh.extra, stale.extra);
    const int coeffs = 3 * NumShCoeffs(s.sh_degree);
    for (int i = n; i < count; ++i) {
      for (int j = 0; j < 3; ++j) EXPECT_EQ(stale.means[3 * i + j], 0.0);
      EXPECT_EQ(stale.opacity_logits[i], 0.0);
      for (int j = 0; j < coeffs; ++j)
        EXPECT_EQ(stale.sh[coeffs * i + j], 0.0);
    }
  }
}

}  // namespace
}  // namespace es
