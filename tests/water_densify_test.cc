#include "solvers/train/water_densify.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace es {
namespace {

TEST(WaterDensifyTest, PicksTheHighestGradientsWithinFractionAndBudget) {
  const std::vector<int> dynamic = {2, 5, 7, 9};
  const std::vector<double> grad = {0.1, 0.4, 0.0, 0.3};
  EXPECT_EQ(PickWaterToDensify(dynamic, grad, 0.5, 100),
            (std::vector<int>{5, 9}));
  // A budget of one more water Gaussian.
  EXPECT_EQ(PickWaterToDensify(dynamic, grad, 0.5, 5), (std::vector<int>{5}));
  EXPECT_TRUE(PickWaterToDensify(dynamic, grad, 0.5, 4).empty());
  // Never seen (gradient 0): never picked.
  EXPECT_EQ(PickWaterToDensify(dynamic, grad, 1.0, 100),
            (std::vector<int>{5, 9, 2}));
  EXPECT_TRUE(PickWaterToDensify(dynamic, grad, 0.0, 100).empty());
}

GaussianSet Gaussians(int n) {
  GaussianSet g;
  g.sh_degree = 0;
  g.Resize(n);
  for (int i = 0; i < n; ++i) {
    g.quats[4 * i] = 1;
    g.opacity_logits[i] = 0.5 + i;
    g.dynamic_logits[i] = 3;
  }
  return g;
}

// Static 0, water 1 (large: split) and 2 (small: cloned).
TEST(WaterDensifyTest, SplitsLargeClonesSmallAndKeepsTheLoopBookkeeping) {
  LoopModel model;
  model.gaussians = Gaussians(3);
  GaussianSet& g = model.gaussians;
  g.dynamic_logits[0] = -3;
  for (int a = 0; a < 3; ++a) {
    g.log_scales[3 * 1 + a] = std::log(0.2);
    g.log_scales[3 * 2 + a] = std::log(0.01);
    g.means[3 * 2 + a] = 1.0;
  }
  GaussianAdam adam;
  adam.Reset(g);
  model.dynamic_index = {1, 2};
  model.start_times = {3, 7};
  std::mt19937_64 rng(1);
  const WaterDensifyResult r =
      DensifyWater({1, 2}, {0.05, 0.05}, 0, &rng, &model, &adam);
  EXPECT_EQ(r.split, 1);
  EXPECT_EQ(r.cloned, 1);
  ASSERT_EQ(g.size(), 5);  // 0, old 2, two children of 1, clone of 2
  EXPECT_EQ(model.dynamic_index, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(model.start_times, (std::vector<int>{7, 3, 3, 7}));
  EXPECT_EQ(g.opacity_logits, (std::vector<double>{0.5, 2.5, 1.5, 1.5, 2.5}));
  EXPECT_EQ(g.dynamic_logits[0], -3);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(std::exp(g.log_scales[3 * 2 + a]), 0.2 / 1.6, 1e-12);
    EXPECT_NEAR(std::exp(g.log_scales[3 * 3 + a]), 0.2 / 1.6, 1e-12);
    EXPECT_NEAR(std::exp(g.log_scales[3 * 4 + a]), 0.01, 1e-12);
    EXPECT_EQ(g.means[3 * 1 + a], 1.0);  // the parent of the clone stays
  }
  // The optimizer state follows: the next step sees the right count.
  GaussianSet grad = Gaussians(5);
  adam.Step(GaussianLearningRates(), grad, &g);
  EXPECT_EQ(g.size(), 5);
}

// With a cycle length, children draw their start times uniformly: one
// parent densified many times does not pile its lineage's loop wraps onto
// one phase (the loop's seam when that phase is 0).
TEST(WaterDensifyTest, ChildrenDrawTheirOwnStartTimes) {
  const int n = 3000, length = 15;
  LoopModel model;
  model.gaussians = Gaussians(n);
  model.dynamic_index.resize(n);
  model.start_times.assign(n, 0);
  std::vector<int> picked(n);
  for (int i = 0; i < n; ++i) model.dynamic_index[i] = picked[i] = i;
  GaussianAdam adam;
  adam.Reset(model.gaussians);
  std::mt19937_64 rng(3);
  DensifyWater(picked, std::vector<double>(n, 1e9), length, &rng, &model,
               &adam);
  const std::vector<int>& starts = model.start_times;
  ASSERT_EQ(starts.size(), 2u * n);  // every parent cloned
  std::vector<int> count(length, 0);
  for (int k = 0; k < n; ++k) EXPECT_EQ(starts[k], 0);  // parents keep theirs
  for (int k = n; k < 2 * n; ++k) {
    ASSERT_GE(starts[k], 0);
    ASSERT_LT(starts[k], length);
    ++count[starts[k]];
  }
  // Uniform: each phase n / L = 200 times, within 5 standard deviations.
  for (int c : count) EXPECT_NEAR(c, n / length, 5 * std::sqrt(n / length));
}

// Split children are drawn from the parent's own normal distribution.
TEST(WaterDensifyTest, ChildrenFillTheParentsVolume) {
  const int n = 4000;
  LoopModel model;
  model.gaussians = Gaussians(n);
  GaussianSet& g = model.gaussians;
  const Eigen::Vector3d scale(0.3, 0.1, 0.05);
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  model.dynamic_index.resize(n);
  model.start_times.assign(n, 0);
  std::vector<int> picked(n);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      g.means[3 * i + a] = 1.0 + a;
      g.log_scales[3 * i + a] = std::log(scale[a]);
    }
    g.quats[4 * i] = q.w();
    g.quats[4 * i + 1] = q.x();
    g.quats[4 * i + 2] = q.y();
    g.quats[4 * i + 3] = q.z();
    model.dynamic_index[i] = picked[i] = i;
  }
  GaussianAdam adam;
  adam.Reset(g);
  std::mt19937_64 rng(2);
  DensifyWater(picked, std::vector<double>(n, 0.01), 0, &rng, &model, &adam);
  ASSERT_EQ(g.size(), 2 * n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < g.size(); ++i) mean += Eigen::Vector3d(&g.means[3 * i]);
  mean /= g.size();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i = 0; i < g.size(); ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(&g.means[3 * i]) - mean;
    cov += d * d.transpose();
  }
  cov /= g.size();
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const Eigen::Matrix3d expected =
      r * scale.array().square().matrix().asDiagonal() * r.transpose();
  EXPECT_LT((mean - Eigen::Vector3d(1, 2, 3)).norm(), 0.02);
  EXPECT_LT((cov - expected).norm(), 0.1 * expected.norm())
      << cov << "\nexpected\n" << expected;
}

}  // namespace
}  // namespace es
