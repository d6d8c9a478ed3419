#include "costs/scene_flow_prior.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

MotionField SmallField() {
  MotionFieldOptions o;
  o.triplane.resolution = 4;
  o.triplane.channels = 2;
  o.mlp_width = 8;
  o.mlp_depth = 2;
  o.velocity_scale = 0.1;
  MotionField field(o);
  field.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  field.Initialize(3);
  return field;
}

// Samples whose velocities all have length `speed`.
std::vector<SceneFlowSample> Samples(int n, double speed) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<SceneFlowSample> samples(n);
  for (SceneFlowSample& s : samples) {
    s.x = Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.v = speed * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  }
  return samples;
}

TEST(SceneFlowPriorTest, WeightDecaysLogLinearly) {
  MotionField field = SmallField();
  FlowPriorOptions options;
  options.weight = 2.0;
  options.final_factor = 0.01;
  const SceneFlowPrior prior(&field, Samples(10, 1.0), options);
  EXPECT_DOUBLE_EQ(prior.Weight(0, 100), 2.0);
  EXPECT_NEAR(prior.Weight(50, 100), 0.2, 1e-12);
  EXPECT_NEAR(prior.Weight(100, 100), 0.02, 1e-12);
  EXPECT_NEAR(prior.Weight(150, 100), 0.02, 1e-12);
}

// V = 0 against samples of one speed: the loss is 0.5 w whatever the
// speed (the prior is relative to the mean squared sample speed).
TEST(SceneFlowPriorTest, LossIsRelativeToTheSampleSpeed) {
  for (double speed : {0.01, 3.0}) {
    MotionField field = SmallField();
    std::fill(field.mlp_params().begin(), field.mlp_params().end(), 0.0);
    FlowPriorOptions options;
    options.weight = 0.4;
    options.batch_size = 32;
    SceneFlowPrior prior(&field, Samples(100, speed), options);
    EXPECT_NEAR(prior.AddLossAndGradient(field.params(), 0, 10, 7, {}), 0.2,
                1e-12)
        << speed;
  }
}

TEST(SceneFlowPriorTest, BatchesDependOnSeedAndIterationOnly) {
  MotionField field = SmallField();
  FlowPriorOptions options;
  options.weight = 1;
  options.final_factor = 1;
  options.batch_size = 8;
  SceneFlowPrior prior(&field, Samples(500, 1.0), options);
  const double a = prior.AddLossAndGradient(field.params(), 3, 10, 1, {});
  prior.AddLossAndGradient(field.params(), 4, 10, 1, {});
  EXPECT_EQ(prior.AddLossAndGradient(field.params(), 3, 10, 1, {}), a);
  EXPECT_NE(prior.AddLossAndGradient(field.params(), 4, 10, 1, {}), a);
  EXPECT_NE(prior.AddLossAndGradient(field.params(), 3, 10, 2, {}), a);
}

TEST(SceneFlowPriorTest, GradientMatchesFiniteDifferences) {
  MotionField field = SmallField();
  FlowPriorOptions options;
  options.weight = 0.7;
  options.batch_size = 16;
  SceneFlowPrior prior(&field, Samples(60, 0.5), options);
  const int n_tri = field.triplane().num_params();
  const int n_mlp = field.mlp().num_params();
  // The gradient is added to what is there.
  std::vector<double> g_tri(n_tri, 1.0), g_mlp(n_mlp, 1.0);
  const int iteration = 4, iterations = 10;
  const uint64_t seed = 11;
  prior.AddLossAndGradient(field.params(), iteration, iterations, seed,
                           {g_tri.data(), g_mlp.data()});
  auto loss = [&] {
    return prior.AddLossAndGradient(field.params(), iteration, iterations,
                                    seed, {});
  };
  const double h = 1e-6;
  auto check = [&](std::vector<double>* params, const std::vector<double>& g,
                   int stride, const char* block) {
    for (size_t k = 0; k < params->size(); k += stride) {
      const double saved = (*params)[k];
      (*params)[k] = saved + h;
      const double plus = loss();
      (*params)[k] = saved - h;
      const double minus = loss();
      (*params)[k] = saved;
      const double numeric = (plus - minus) / (2 * h);
      EXPECT_NEAR(g[k] - 1.0, numeric, 1e-6 + 1e-4 * std::abs(numeric))
          << block << " " << k;
    }
  };
  check(&field.triplane_params(), g_tri, 3, "triplane");
  check(&field.mlp_params(), g_mlp, 1, "mlp");
}

// Targets taken from the field itself: the prior is 0 there, with no
// gradient, and grows as the field leaves them.
TEST(SceneFlowPriorTest, TargetsFromTheFieldHoldItWhereItIs) {
  MotionField field = SmallField();
  std::vector<SceneFlowSample> samples = Samples(40, 0.5);
  for (SceneFlowSample& s : samples) s.unseen = Eigen::Vector3d(0, 0, 1);
  TargetFieldAtSamples(field, &samples);
  FieldWorkspace ws;
  for (const SceneFlowSample& s : samples) {
    Eigen::Vector3d v;
    field.Evaluate(field.params(), 1, s.x.data(), v.data(), &ws);
    EXPECT_NEAR((v - s.v).norm(), 0, 1e-12);
    EXPECT_EQ(s.unseen, Eigen::Vector3d::Zero());
  }
  FlowPriorOptions options;
  options.weight = 1;
  options.batch_size = 40;
  SceneFlowPrior prior(&field, samples, options);
  std::vector<double> g_mlp(field.mlp().num_params(), 0.0);
  EXPECT_NEAR(prior.AddLossAndGradient(field.params(), 0, 10, 3,
                                       {nullptr, g_mlp.data()}),
              0, 1e-20);
  for (double g : g_mlp) EXPECT_EQ(g, 0);
  // Targets 1/1.1 of V: the loss is about 0.5 * 0.1^2 (exactly so over
  // all samples; the batch is drawn with replacement).
  std::vector<SceneFlowSample> slower = samples;
  for (SceneFlowSample& s : slower) s.v /= 1.1;
  SceneFlowPrior slower_prior(&field, slower, options);
  const double loss_scaled =
      slower_prior.AddLossAndGradient(field.params(), 0, 10, 3, {});
  EXPECT_NEAR(loss_scaled, 0.5 * 0.1 * 0.1, 0.5 * 0.1 * 0.1 * 0.5);
}

}  // namespace
}  // namespace es
