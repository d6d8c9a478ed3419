#include "costs/scene_flow_cost.h"

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include "tests/plane_combination_name.h"
#include "tests/random_scene_flow_samples.h"

namespace es {
namespace {

MotionFieldOptions TinyFieldOptions(PlaneCombination combination) {
  MotionFieldOptions o;
  o.triplane.resolution = 4;
  o.triplane.channels = 3;
  o.triplane.combination = combination;
  o.triplane.init_noise = 0.5;
  o.mlp_width = 5;
  o.mlp_depth = 2;
  o.velocity_scale = 0.3;
  o.last_layer_init_scale = 1.0;  // a non-trivial output to differentiate
  o.seed = 3;
  return o;
}

std::vector<SceneFlowSample> RandomSamples(int n, uint32_t seed) {
  return RandomSceneFlowSamples(n, seed, 0.9, 0.2);
}

// P_s (V - V') for sample s, computed apart from the cost.
Eigen::Vector3d ConstrainedDifference(const SceneFlowBatch& batch,
                                      const std::vector<double>& v, int s) {
  const Eigen::Vector3d d =
      Eigen::Vector3d(&v[3 * s]) - Eigen::Vector3d(&batch.target[3 * s]);
  const Eigen::Vector3d u(&batch.unseen[3 * s]);
  return d - d.dot(u) * u;
}

// GradientChecker differentiates with Ridders' method, whose first step
// (1e-2 relative by default) crosses the MLP's ReLU kinks (one sat 3e-5 from
// a probe here); a first step of 1e-6 keeps each probe on one linear piece.
ceres::NumericDiffOptions KinkSafeDiffOptions() {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-6;
  return options;
}

// Probes `cost` at two random perturbations of the field's parameters, to a
// relative 1e-5: Jacobian entries of 1e-6 carry 1e-11 of round-off in the
// numeric differences.
void ExpectGradientsMatch(const ceres::CostFunction& cost,
                          MotionField* field) {
  std::vector<double> tri = field->triplane_params();
  std::vector<double> mlp = field->mlp_params();
  const ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr),
      KinkSafeDiffOptions());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.05);
  // Perturbed before every probe: the initial biases are zero, which puts a
  // second-layer unit exactly on its kink when the first layer is all off.
  for (int probe = 0; probe < 2; ++probe) {
    for (double& p : tri) p += noise(rng);
    for (double& p : mlp) p += noise(rng);
    const double* blocks[2] = {tri.data(), mlp.data()};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks, 1e-5, &results)) << results.error_log;
  }
}

class SceneFlowCostTest : public ::testing::TestWithParam<PlaneCombination> {
 protected:
  SceneFlowCostTest() : field_(TinyFieldOptions(GetParam())) {
    field_.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
    batch_.AssignAll(RandomSamples(6, 1));
  }
  MotionField field_;
  SceneFlowBatch batch_;
};

TEST_P(SceneFlowCostTest, ScalarCostGradientMatchesNumericDiff) {
  const SceneFlowCost cost(&field_, &batch_);
  ExpectGradientsMatch(cost, &field_);
}

TEST_P(SceneFlowCostTest, ResidualsGradientMatchesNumericDiff) {
  const SceneFlowResiduals cost(&field_, &batch_);
  ExpectGradientsMatch(cost, &field_);
}

TEST_P(SceneFlowCostTest, ResidualIsSqrtOfTwiceTheMeanHalfSquaredError) {
  const double eps = 1e-9;
  const SceneFlowCost cost(&field_, &batch_, eps);
  const int n = batch_.size();
  std::vector<double> v(3 * n);
  FieldWorkspace ws;
  field_.Evaluate(field_.params(), n, batch_.x.data(), v.data(), &ws);
  double l = 0;
  for (int s = 0; s < n; ++s) {
    l += 0.5 * ConstrainedDifference(batch_, v, s).squaredNorm() / n;
  }
  const double* blocks[2] = {field_.params().triplane, field_.params().mlp};
  double r = 0;
  ASSERT_TRUE(cost.Evaluate(blocks, &r, nullptr));
  EXPECT_NEAR(r, std::sqrt(2 * l + eps), 1e-12);
  EXPECT_NEAR(cost.Loss(field_.params(), {}), l, 1e-14);

  // The least-squares variant's residuals are the per-sample differences.
  const SceneFlowResiduals residuals(&field_, &batch_);
  std::vector<double> res(3 * n);
  ASSERT_TRUE(residuals.Evaluate(blocks, res.data(), nullptr));
  for (int s = 0; s < n; ++s) {
    const Eigen::Vector3d d = ConstrainedDifference(batch_, v, s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(res[3 * s + c], d[c], 1e-12);
  }
}

TEST_P(SceneFlowCostTest, MotionAlongTheUnseenDirectionIsFree) {
  // Moving a target along its sample's unit unseen direction changes
  // nothing; moving it across does, and so does any change where there is
  // none. (A shorter unseen direction keeps part of the residual along it:
  // ConstrainedDifference above and the gradient checks cover it.)
  const SceneFlowCost cost(&field_, &batch_);
  const double base = cost.Loss(field_.params(), {});
  for (int s = 0; s < batch_.size(); ++s) {
    const Eigen::Vector3d u(&batch_.unseen[3 * s]);
    if (!u.isZero() && std::abs(u.norm() - 1) > 1e-12) continue;
    const Eigen::Vector3d across =
        u.isZero() ? Eigen::Vector3d(0.1, 0, 0)
                   : u.cross(Eigen::Vector3d(1, 0, 0)).normalized() * 0.1;
    SceneFlowBatch moved = batch_;
    for (int c = 0; c < 3; ++c) moved.target[3 * s + c] += 0.3 * u[c];
    EXPECT_NEAR(SceneFlowCost(&field_, &moved).Loss(field_.params(), {}),
                base, 1e-14);
    moved = batch_;
    for (int c = 0; c < 3; ++c) moved.target[3 * s + c] += across[c];
    EXPECT_GT(std::abs(SceneFlowCost(&field_, &moved).Loss(field_.params(),
                                                           {}) -
                       base),
              1e-6);
  }
}

TEST_P(SceneFlowCostTest, ProblemEvaluateReturnsTheLossGradient) {
  // With r = sqrt(2 l + eps), Ceres' gradient J^T r is exactly dl/dtheta.
  std::vector<double> tri = field_.triplane_params();
  std::vector<double> mlp = field_.mlp_params();
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(options);
  SceneFlowCost cost(&field_, &batch_);
  problem.AddResidualBlock(&cost, nullptr, tri.data(), mlp.data());
  double ceres_cost = 0;
  std::vector<double> gradient;
  ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), &ceres_cost,
                               nullptr, &gradient, nullptr));

  std::vector<double> d_tri(tri.size(), 0.0), d_mlp(mlp.size(), 0.0);
  const double l =
      cost.Loss({tri.data(), mlp.data()}, {d_tri.data(), d_mlp.data()});
  EXPECT_NEAR(ceres_cost, l, 1e-10);  // Ceres' cost is r^2 / 2
  ASSERT_EQ(gradient.size(), tri.size() + mlp.size());
  for (size_t i = 0; i < tri.size(); ++i) {
    EXPECT_NEAR(gradient[i], d_tri[i], 1e-12);
  }
  for (size_t i = 0; i < mlp.size(); ++i) {
    EXPECT_NEAR(gradient[tri.size() + i], d_mlp[i], 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(Combinations, SceneFlowCostTest,
                         AllPlaneCombinations());

// The checker must be able to fail: a cost whose Jacobian is 1% off.
class SkewedSceneFlowCost : public SceneFlowCost {
 public:
  using SceneFlowCost::SceneFlowCost;
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!SceneFlowCost::Evaluate(parameters, residuals, jacobians)) {
      return false;
    }
    if (jacobians != nullptr && jacobians[1] != nullptr) {
      for (int i = 0; i < parameter_block_sizes()[1]; ++i) {
        jacobians[1][i] *= 1.01;
      }
    }
    return true;
  }
};

TEST(SceneFlowCostCheckTest, WrongJacobianIsDetected) {
  MotionField field(TinyFieldOptions(PlaneCombination::kSum));
  field.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  SceneFlowBatch batch;
  batch.AssignAll(RandomSamples(4, 2));
  const SkewedSceneFlowCost cost(&field, &batch);
  const ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr),
      KinkSafeDiffOptions());
  const double* blocks[2] = {field.params().triplane, field.params().mlp};
  ceres::GradientChecker::ProbeResults results;
  EXPECT_FALSE(checker.Probe(blocks, 1e-6, &results));
}

TEST(SceneFlowCostCheckTest, EmptyBatchHasZeroLoss) {
  MotionField field(TinyFieldOptions(PlaneCombination::kSum));
  field.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  SceneFlowBatch batch;
  const SceneFlowCost cost(&field, &batch);
  EXPECT_EQ(cost.Loss(field.params(), {}), 0.0);
}

}  // namespace
}  // namespace es
