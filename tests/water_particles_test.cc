#include "solvers/train/water_particles.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/centered_camera.h"

namespace es {
namespace {

// One camera at the origin looking down +z with fx = 100.
std::vector<Frame> OneCamera() {
  std::vector<Frame> frames(1);
  frames[0].camera = CenteredCamera(200, 100, 100);
  return frames;
}

// Gaussian 0 static, 1 a large water blob at depth 10 on the axis (std
// devs 0.5, 0.2, 0.05 along x, y, z), 2 a water Gaussian already
// particle-sized.
GaussianSet Scene() {
  GaussianSet g;
  g.sh_degree = 0;
  g.Resize(3);
  const double z[3] = {12, 10, 10};
  for (int n = 0; n < 3; ++n) {
    g.means[3 * n + 2] = z[n];
    g.opacity_logits[n] = 0.3 * n;
    g.sh[3 * n] = 0.1 * n;
    g.dynamic_logits[n] = n == 0 ? -4 : 4;
  }
  g.means[6] = 1.0;  // the blob is on the optical axis
  const double blob[3] = {0.5, 0.2, 0.05};
  for (int a = 0; a < 3; ++a) {
    g.log_scales[a] = std::log(1.0);
    g.log_scales[3 + a] = std::log(blob[a]);
    g.log_scales[6 + a] = std::log(0.004);
  }
  return g;
}

TEST(WaterParticlesTest, PixelSizeScalesWithDistance) {
  const GaussianSet g = Scene();
  const std::vector<double> s =
      PixelSizeInWorld(g, {0, 1}, OneCamera(), {0}, 2.0);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0], 2.0 * 12 / 100, 1e-12);
  EXPECT_NEAR(s[1], 2.0 * 10 / 100, 1e-12);
}

TEST(WaterParticlesTest, SplitsLargeWaterIntoParticlesFillingIt) {
  GaussianSet g = Scene();
  WaterParticleOptions o;
  o.particle_pixels = 1.0;  // 0.1 world units at depth 10
  o.max_children = 1000;
  o.max_particles = 100000;
  const ParticleSplitStats stats =
      SplitWaterIntoParticles(o, OneCamera(), {0}, &g);
  EXPECT_EQ(stats.blobs, 1);
  EXPECT_EQ(stats.dynamic_before, 2);
  // Screen area 0.5 x 0.2 over 0.1 x 0.1.
  EXPECT_EQ(stats.particles, 10);
  EXPECT_EQ(stats.dynamic_after, 11);
  ASSERT_EQ(g.size(), 12);
  // The static Gaussian and the small water one come first, unchanged.
  EXPECT_EQ(g.dynamic_logits[0], -4);
  EXPECT_EQ(g.log_scales[0], 0.0);
  EXPECT_EQ(g.means[5], 10);
  EXPECT_DOUBLE_EQ(g.log_scales[3], std::log(0.004));
  for (int n = 2; n < g.size(); ++n) {
    EXPECT_EQ(g.dynamic_logits[n], 4);
    EXPECT_DOUBLE_EQ(g.opacity_logits[n], 0.3);
    EXPECT_NEAR(std::exp(g.log_scales[3 * n]), 0.1, 1e-12);
    EXPECT_NEAR(std::exp(g.log_scales[3 * n + 1]), 0.1, 1e-12);
    EXPECT_NEAR(std::exp(g.log_scales[3 * n + 2]), 0.05, 1e-12);  // thinner
  }
}

TEST(WaterParticlesTest, ParticlesFollowTheBlobsDistribution) {
  GaussianSet g = Scene();
  WaterParticleOptions o;
  o.particle_pixels = 0.05;  // area ratio 0.5 x 0.2 / 0.005^2 = 4000
  o.max_children = 4000;
  o.max_particles = 100000;
  SplitWaterIntoParticles(o, OneCamera(), {0}, &g);
  ASSERT_EQ(g.size(), 4002);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), sq = mean;
  for (int n = 2; n < g.size(); ++n) {
    const Eigen::Vector3d x(&g.means[3 * n]);
    mean += x;
    sq += x.cwiseProduct(x);
  }
  mean /= 4000;
  const Eigen::Vector3d sd =
      (sq / 4000 - mean.cwiseProduct(mean)).cwiseSqrt();
  EXPECT_NEAR(mean.x(), 0.0, 0.03);
  EXPECT_NEAR(mean.z(), 10.0, 0.01);
  EXPECT_NEAR(sd.x(), 0.5, 0.03);
  EXPECT_NEAR(sd.y(), 0.2, 0.012);
  EXPECT_NEAR(sd.z(), 0.05, 0.003);
}

TEST(WaterParticlesTest, BudgetLimitsTheParticleCount) {
  GaussianSet g = Scene();
  WaterParticleOptions o;
  o.particle_pixels = 0.05;
  o.max_children = 4000;
  o.max_particles = 101;  // the small water Gaussian is one of them
  const ParticleSplitStats stats =
      SplitWaterIntoParticles(o, OneCamera(), {0}, &g);
  EXPECT_EQ(stats.particles, 100);
  EXPECT_EQ(stats.dynamic_after, 101);
  o.max_children = 16;
  GaussianSet h = Scene();
  EXPECT_EQ(SplitWaterIntoParticles(o, OneCamera(), {0}, &h).particles, 16);
}

TEST(WaterParticlesTest, ClampScalesCapsOnlyTheListedGaussians) {
  GaussianSet g = Scene();
  EXPECT_EQ(ClampScales({1}, {0.1}, &g), 2);  // the 0.5 and 0.2 axes
  EXPECT_DOUBLE_EQ(g.log_scales[3], std::log(0.1));
  EXPECT_DOUBLE_EQ(g.log_scales[4], std::log(0.1));
  EXPECT_DOUBLE_EQ(g.log_scales[5], std::log(0.05));
  EXPECT_EQ(g.log_scales[0], 0.0);
}

}  // namespace
}  // namespace es
