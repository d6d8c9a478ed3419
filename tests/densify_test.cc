#include "solvers/train/densify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/model/gaussian_init.h"
#include "core/render/rasterizer.h"

namespace es {
namespace {

// Two Gaussians: 0 is small, 1 is large (relative to extent 10 * 0.01).
GaussianSet TwoGaussians() {
  GaussianSet g;
  g.sh_degree = 0;
  g.Resize(2);
  g.means = {0, 0, 5, 1, 0, 5};
  g.log_scales = {std::log(0.05), std::log(0.05), std::log(0.05),
                  std::log(0.5),  std::log(0.2),  std::log(0.2)};
  g.opacity_logits = {Logit(0.5), Logit(0.5)};
  g.sh = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  g.dynamic_logits = {1.0, -1.0};
  return g;
}

struct Fixture {
  GaussianSet g = TwoGaussians();
  GaussianAdam adam;
  DensityStats stats;
  std::mt19937_64 rng{7};
  DensifyOptions options;
  Fixture() {
    adam.Reset(g);
    adam.m().means.assign(6, 1.0);
    stats.Reset(2);
  }
  // One densification step in a world of extent `extent`; `prune_large`
  // also prunes the Gaussians too big on screen or in the world.
  DensifyResult Densify(double extent = 10.0, bool prune_large = false) {
    return DensifyAndPrune(options, extent, prune_large, &rng, &g, &adam,
                           &stats);
  }
  // Both Gaussians seen once, with these accumulated gradients.
  void SetGradients(double first, double second) {
    stats.grad_sum = {first, second};
    stats.count = {1, 1};
  }
};

TEST(DensifyTest, ClonesSmallAndSplitsLargeAboveThreshold) {
  Fixture f;
  f.SetGradients(1e-3, 1e-3);
  const DensifyResult r = f.Densify();
  EXPECT_EQ(r.cloned, 1);
  EXPECT_EQ(r.split, 1);
  EXPECT_EQ(r.pruned, 0);
  // Kept: original 0; added: its clone, then two halves of 1.
  ASSERT_EQ(f.g.size(), 4);
  EXPECT_EQ(f.g.means[3 * 1], 0.0);  // the clone sits on its source
  EXPECT_EQ(f.g.sh[3], 0.1);
  for (int j = 2; j < 4; ++j) {
    EXPECT_NEAR(f.g.log_scales[3 * j], std::log(0.5 / 1.6), 1e-12);
    EXPECT_EQ(f.g.dynamic_logits[j], -1.0);
    EXPECT_NE(f.g.means[3 * j], 1.0);  // sampled inside the parent
    EXPECT_LT(std::abs(f.g.means[3 * j] - 1.0), 5 * 0.5);
  }
  // Moments: the kept Gaussian keeps its own, new ones start at zero.
  EXPECT_EQ(f.adam.m().size(), 4);
  EXPECT_EQ(f.adam.m().means[0], 1.0);
  EXPECT_EQ(f.adam.m().means[3], 0.0);
  EXPECT_EQ(f.stats.size(), 4);
  EXPECT_EQ(f.stats.grad_sum[0], 0.0);  // stats reset
}

TEST(DensifyTest, BelowThresholdNothingChanges) {
  Fixture f;
  f.SetGradients(1e-4, 1e-5);
  const DensifyResult r = f.Densify();
  EXPECT_EQ(r.cloned + r.split + r.pruned, 0);
  EXPECT_EQ(f.g.means, TwoGaussians().means);
}

TEST(DensifyTest, PrunesTransparentAndTooLarge) {
  Fixture f;
  f.g.opacity_logits[0] = Logit(0.001);
  DensifyResult r = f.Densify();
  EXPECT_EQ(r.pruned, 1);
  ASSERT_EQ(f.g.size(), 1);
  EXPECT_EQ(f.g.means[0], 1.0);
  EXPECT_EQ(f.adam.m().size(), 1);
  // Gaussian 1 (max scale 0.5) is too large in a world of extent 4 when
  // the world-size prune is on (it is off by default).
  r = f.Densify(4.0, true);
  EXPECT_EQ(r.pruned, 0);
  f.options.max_world_scale = 0.1;
  r = f.Densify(4.0, true);
  EXPECT_EQ(r.pruned, 1);
  EXPECT_EQ(f.g.size(), 0);
}

TEST(DensifyTest, CapLimitsGrowthToHighestGradients) {
  Fixture f;
  f.options.max_gaussians = 3;
  f.SetGradients(1e-3, 5e-3);
  const DensifyResult r = f.Densify();
  EXPECT_EQ(r.split, 1);  // the higher gradient wins the single slot
  EXPECT_EQ(r.cloned, 0);
  EXPECT_EQ(f.g.size(), 3);
}

TEST(DensifyTest, ResetOpacityCapsAndClearsMoments) {
  Fixture f;
  f.g.opacity_logits = {Logit(0.9), Logit(0.001)};
  f.adam.m().opacity_logits = {3, 3};
  ResetOpacity(0.01, &f.g, &f.adam);
  EXPECT_NEAR(Sigmoid(f.g.opacity_logits[0]), 0.01, 1e-12);
  EXPECT_NEAR(Sigmoid(f.g.opacity_logits[1]), 0.001, 1e-12);
  EXPECT_EQ(f.adam.m().opacity_logits[0], 0.0);
}

TEST(DensifyTest, AccumulatesRasterizerViewSpaceGradientInNdc) {
  // A non-square view, so swapping the W/2 and H/2 factors would show.
  Camera cam;
  cam.width = 64, cam.height = 40;
  cam.fx = cam.fy = 40, cam.cx = 32, cam.cy = 20;
  GaussianSet g;
  g.sh_degree = 0;
  g.Resize(3);
  g.means = {0,  0, 4,    // on the optical axis
             20, 0, 4,    // far right of the image: culled
             0,  0, -4};  // behind the camera: culled
  g.log_scales.assign(9, std::log(0.3));
  g.opacity_logits.assign(3, Logit(0.9));
  g.sh.assign(9, 0.4);
  Rasterizer rasterizer;
  RenderOptions options;
  options.use_double = true;
  RenderResult out;
  rasterizer.Forward(cam, SplatView::Of(g), options, &out);
  // Red rewarded right of the mean and green below it: both components of
  // the screen-space gradient are non-zero.
  std::vector<double> d_rgb(out.rgb.size(), 0.0);
  for (int i = 0; i < cam.height; ++i)
    for (int j = 0; j < cam.width; ++j) {
      d_rgb[3 * (i * cam.width + j)] = j >= 32 ? 1.0 : 0.0;
      d_rgb[3 * (i * cam.width + j) + 1] = i >= 20 ? 0.5 : 0.0;
    }
  SplatGradients grads;
  rasterizer.Backward({d_rgb.data(), nullptr, nullptr, nullptr}, &grads);
  std::vector<int> radii;
  std::vector<double> mean2d;
  rasterizer.Radii(&radii);
  rasterizer.Mean2dGradients(&mean2d);
  ASSERT_GT(radii[0], 0);
  ASSERT_GT(std::abs(mean2d[0]), 1e-3);
  ASSERT_GT(std::abs(mean2d[1]), 1e-3);

  DensityStats stats;
  stats.Reset(3);
  stats.AddView(cam.width, cam.height, radii, mean2d);
  stats.AddView(cam.width, cam.height, radii, mean2d);
  // On the axis an isotropic footprint does not change to first order when
  // the Gaussian moves sideways, so d loss / d u = z / fx * d loss / d x:
  // the NDC gradient follows from the world gradient independently.
  const double ndc_u = grads.means[0] * 4 / cam.fx * cam.width / 2;
  const double ndc_v = grads.means[1] * 4 / cam.fy * cam.height / 2;
  EXPECT_NEAR(stats.MeanGrad(0), std::hypot(ndc_u, ndc_v),
              1e-9 * std::hypot(ndc_u, ndc_v));
  EXPECT_EQ(stats.count[0], 2);
  EXPECT_EQ(stats.max_radius[0], radii[0]);
  for (int i : {1, 2}) {
    EXPECT_EQ(radii[i], 0) << i;
    EXPECT_EQ(stats.count[i], 0) << i;
    EXPECT_EQ(stats.grad_sum[i], 0) << i;
    EXPECT_EQ(stats.MeanGrad(i), 0) << i;
  }
}

TEST(KnnInitTest, MatchesBruteForceAndSeedsAttributes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> pts, colors;
  for (int i = 0; i < 500; ++i) {
    pts.emplace_back(u(rng), u(rng), 0.1 * u(rng));  // flattened cloud
    colors.emplace_back(0.5 + 0.5 * u(rng), 0.2, 0.9);
  }
  pts.push_back(pts[0]);  // a duplicate
  colors.push_back(colors[0]);
  const std::vector<double> d2 = MeanSquaredKnnDistances(pts, 3);
  for (size_t i = 0; i < pts.size(); ++i) {
    std::vector<double> all;
    for (size_t j = 0; j < pts.size(); ++j)
      if (j != i) all.push_back((pts[i] - pts[j]).squaredNorm());
    std::sort(all.begin(), all.end());
    EXPECT_NEAR(d2[i], (all[0] + all[1] + all[2]) / 3, 1e-15) << i;
  }
  const GaussianSet g = InitGaussiansFromPoints(pts, colors, 1);
  g.CheckConsistent();
  ASSERT_EQ(g.size(), 501);
  EXPECT_NEAR(g.log_scales[4], 0.5 * std::log(d2[1]), 1e-12);
  EXPECT_NEAR(kShC0 * g.sh[4 * 3 * 7 + 2] + 0.5, 0.9, 1e-12);
  EXPECT_EQ(g.sh[4 * 3 * 7 + 3], 0.0);  // higher bands start at zero
  EXPECT_NEAR(Sigmoid(g.opacity_logits[9]), 0.1, 1e-12);
  EXPECT_EQ(g.quats[4 * 9], 1.0);
  EXPECT_EQ(g.dynamic_logits[9], 0.0);
  EXPECT_TRUE(std::isfinite(g.log_scales[3 * 500]));
}

}  // namespace
}  // namespace es
