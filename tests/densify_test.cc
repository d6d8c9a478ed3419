#include "solvers/densify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/knn_init.h"

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
};

TEST(DensifyTest, ClonesSmallAndSplitsLargeAboveThreshold) {
  Fixture f;
  f.stats.grad_sum = {1e-3, 1e-3};
  f.stats.count = {1, 1};
  const DensifyResult r =
      DensifyAndPrune(f.options, 10.0, false, &f.rng, &f.g, &f.adam, &f.stats);
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
  f.stats.grad_sum = {1e-4, 1e-5};
  f.stats.count = {1, 1};
  const DensifyResult r =
      DensifyAndPrune(f.options, 10.0, false, &f.rng, &f.g, &f.adam, &f.stats);
  EXPECT_EQ(r.cloned + r.split + r.pruned, 0);
  EXPECT_EQ(f.g.means, TwoGaussians().means);
}

TEST(DensifyTest, PrunesTransparentAndTooLarge) {
  Fixture f;
  f.g.opacity_logits[0] = Logit(0.001);
  DensifyResult r =
      DensifyAndPrune(f.options, 10.0, false, &f.rng, &f.g, &f.adam, &f.stats);
  EXPECT_EQ(r.pruned, 1);
  ASSERT_EQ(f.g.size(), 1);
  EXPECT_EQ(f.g.means[0], 1.0);
  EXPECT_EQ(f.adam.m().size(), 1);
  // Gaussian 1 (max scale 0.5) is too large in a world of extent 4.
  r = DensifyAndPrune(f.options, 4.0, true, &f.rng, &f.g, &f.adam, &f.stats);
  EXPECT_EQ(r.pruned, 1);
  EXPECT_EQ(f.g.size(), 0);
}

TEST(DensifyTest, CapLimitsGrowthToHighestGradients) {
  Fixture f;
  f.options.max_gaussians = 3;
  f.stats.grad_sum = {1e-3, 5e-3};
  f.stats.count = {1, 1};
  const DensifyResult r =
      DensifyAndPrune(f.options, 10.0, false, &f.rng, &f.g, &f.adam, &f.stats);
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

TEST(DensifyTest, ViewGradientIsImagePlaneComponentInNdc) {
  GaussianSet g = TwoGaussians();
  Camera cam;
  cam.width = 100, cam.height = 80;
  cam.fx = cam.fy = 50, cam.cx = 50, cam.cy = 40;
  DensityStats stats;
  stats.Reset(2);
  // Gaussian 0 at depth 5: moving it by dx moves its image by fx dx / z, so
  // d/du = d/dx * z / fx; NDC scales by W / 2. Depth gradient is ignored.
  const std::vector<double> d_means = {0.01, 0.0, 7.0, 0.0, 0.0, 0.0};
  stats.AddView(cam, g, d_means.data());
  EXPECT_NEAR(stats.grad_sum[0], 0.01 * 5 / 50 * 50, 1e-15);
  EXPECT_EQ(stats.count[0], 1);
  EXPECT_EQ(stats.count[1], 1);
  EXPECT_NEAR(stats.max_radius[0], 3 * 0.05 * 50 / 5, 1e-12);
  cam.t_cw = {0, 0, -10};  // now both are behind the camera
  stats.AddView(cam, g, d_means.data());
  EXPECT_EQ(stats.count[0], 1);
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
