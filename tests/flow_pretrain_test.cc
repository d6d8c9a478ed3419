#include "solvers/train/flow_pretrain.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_pretrain_steps.h"
#include "tests/expect_error.h"
#include "tests/small_fields.h"

namespace es {
namespace {

// A smooth swirl with a vertical component, displacement per frame.
Eigen::Vector3d TrueVelocity(const Eigen::Vector3d& x) {
  return 0.04 * Eigen::Vector3d(std::sin(1.5 * x.y()) + 0.3,
                                -std::sin(1.5 * x.x()),
                                0.5 * std::cos(x.x() + x.y()));
}

std::vector<SceneFlowSample> SamplesOf(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<SceneFlowSample> samples(n);
  for (SceneFlowSample& s : samples) {
    s.x = Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.v = TrueVelocity(s.x);
  }
  return samples;
}

MotionField SmallField(int resolution, int channels, int width) {
  MotionFieldOptions o;
  SetFieldSize(resolution, channels, width, &o);
  o.mlp_depth = 2;
  MotionField field(o);
  field.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  return field;
}

// es_flowinit with absurd rates used to write a NaN field and
// "fit_rmse": -nan and exit 0; every solver now throws instead.
TEST(FlowPretrainTest, DivergenceThrowsInsteadOfReturningANanField) {
  const std::vector<SceneFlowSample> samples = SamplesOf(300, 1);
  for (PretrainSolver solver :
       {PretrainSolver::kAdam, PretrainSolver::kLbfgs, PretrainSolver::kLm}) {
    MotionField field = SmallField(4, 2, 4);
    FlowPretrainOptions options;
    options.solver = solver;
    options.iterations = 20;
    options.batch_size = 64;
    options.lr_triplane = NAN;
    options.lr_mlp = NAN;
    std::vector<SceneFlowSample> bad = samples;
    if (solver != PretrainSolver::kAdam) bad[0].v.x() = NAN;
    EXPECT_THROW(PretrainMotionField(bad, options, &field), TrainingDiverged)
        << PretrainSolverName(solver);
  }
  // Adam on samples with a NaN: every batch that draws it is skipped.
  MotionField field = SmallField(4, 2, 4);
  std::vector<SceneFlowSample> bad = samples;
  for (SceneFlowSample& s : bad) s.v.x() = NAN;
  FlowPretrainOptions options;
  options.iterations = 50;
  options.batch_size = 16;
  options.max_nonfinite_steps = 5;
  EXPECT_THROW(PretrainMotionField(bad, options, &field), TrainingDiverged);
}

// D (issue 46): es_flowinit --lr_mlp 1e30 ended with fit_rmse 5.7e60 and
// exit 0. The first step's runaway MLP now stops the fit, naming the flag;
// so does a fit whose RMSE grew a thousandfold, whatever the solver.
TEST(FlowPretrainTest, RunawayFitStopsNamingTheLearningRate) {
  const std::vector<SceneFlowSample> samples = SamplesOf(300, 1);
  MotionField field = SmallField(4, 2, 4);
  FlowPretrainOptions options;
  options.iterations = 20;
  options.batch_size = 64;
  options.lr_mlp = 1e30;
  ExpectErrorNaming<TrainingDiverged>(
      [&] { PretrainMotionField(samples, options, &field); },
      {"--lr_mlp 1e+30"});

  FlowPretrainReport report;
  report.initial_rmse = 0.02;
  report.target_rms = 0.03;
  report.fit_rmse = 0.01;
  CheckPretrainedField(true, report, FlowPretrainOptions());
  report.fit_rmse = 29.9;  // under 1000 x 0.03
  CheckPretrainedField(true, report, FlowPretrainOptions());
  report.fit_rmse = 5.7e60;
  ExpectErrorNaming<TrainingDiverged>(
      [&] { CheckPretrainedField(true, report, FlowPretrainOptions()); },
      {"5.7e+60", "--lr_triplane 0.01", "--lr_mlp 0.001"});
  FlowPretrainOptions lbfgs;
  lbfgs.solver = PretrainSolver::kLbfgs;
  EXPECT_THROW(CheckPretrainedField(true, report, lbfgs), TrainingDiverged);
}

TEST(FlowPretrainTest, AdamFitsASmoothFieldAndGeneralizes) {
  MotionField field = SmallField(12, 6, 32);
  const std::vector<SceneFlowSample> samples = SamplesOf(3000, 1);
  FlowPretrainOptions options;
  options.iterations = 800;
  options.batch_size = 512;
  const FlowPretrainReport report =
      PretrainMotionField(samples, options, &field);
  EXPECT_EQ(report.num_samples, 3000);
  EXPECT_EQ(report.iterations, 800);
  EXPECT_NEAR(report.initial_rmse, report.target_rms,
              0.05 * report.target_rms);  // V starts near zero
  EXPECT_LT(report.fit_rmse, 0.05 * report.target_rms);
  EXPECT_DOUBLE_EQ(report.fit_rmse, FitRmse(field, samples));
  // Points it never saw: the field itself was learned, not the samples.
  EXPECT_LT(FitRmse(field, SamplesOf(1000, 2)), 0.08 * report.target_rms);
}

// The second-order solvers on a field and sample count each handles in a
// test's time (Levenberg-Marquardt's dense Jacobian wants a tiny field).
struct SolverCase {
  const char* name;
  PretrainSolver solver;
  int resolution, channels, width;
  int samples, iterations, batch_size;
  double max_relative_rmse;  // fit RMSE / the targets' RMS
};

class FlowPretrainSolverTest : public ::testing::TestWithParam<SolverCase> {};

TEST_P(FlowPretrainSolverTest, FitsASmoothField) {
  const SolverCase& c = GetParam();
  MotionField field = SmallField(c.resolution, c.channels, c.width);
  const std::vector<SceneFlowSample> samples = SamplesOf(c.samples, 1);
  FlowPretrainOptions options;
  options.solver = c.solver;
  options.iterations = c.iterations;
  if (c.batch_size > 0) options.batch_size = c.batch_size;
  const FlowPretrainReport report =
      PretrainMotionField(samples, options, &field);
  EXPECT_LT(report.fit_rmse, c.max_relative_rmse * report.target_rms);
}

INSTANTIATE_TEST_SUITE_P(
    Solvers, FlowPretrainSolverTest,
    ::testing::Values(
        SolverCase{"Lbfgs", PretrainSolver::kLbfgs, 12, 6, 32, 1500, 300, 0,
                   0.05},
        SolverCase{"LevenbergMarquardt", PretrainSolver::kLm, 4, 3, 8, 300, 50,
                   300, 0.1}),
    [](const ::testing::TestParamInfo<SolverCase>& info) {
      return std::string(info.param.name);
    });

TEST(FlowPretrainTest, ProgressIsReportedWithDecreasingError) {
  MotionField field = SmallField(8, 4, 16);
  const std::vector<SceneFlowSample> samples = SamplesOf(500, 3);
  FlowPretrainOptions options;
  options.iterations = 200;
  options.batch_size = 500;
  options.log_every = 50;
  std::vector<double> rmse;
  options.progress = [&](int, double, double r) { rmse.push_back(r); };
  PretrainMotionField(samples, options, &field);
  ASSERT_EQ(rmse.size(), 4u);
  EXPECT_LT(rmse.back(), 0.5 * rmse.front());
}

TEST(FlowPretrainTest, TotalVariationSmoothsUntouchedTexels) {
  // Samples only in the lower half of the box: without TV the upper texels
  // keep their initial noise; with TV they follow their neighbours.
  std::vector<SceneFlowSample> samples = SamplesOf(1000, 4);
  for (SceneFlowSample& s : samples) s.x.z() = -std::abs(s.x.z());
  FlowPretrainOptions options;
  options.iterations = 300;
  options.batch_size = 500;
  double tv[2];
  for (int with_tv = 0; with_tv < 2; ++with_tv) {
    MotionField field = SmallField(8, 4, 16);
    options.tv_weight = with_tv ? 1.0 : 0.0;
    PretrainMotionField(samples, options, &field);
    tv[with_tv] = field.triplane().TotalVariation(
        field.triplane_params().data(), 1.0, nullptr);
  }
  EXPECT_LT(tv[1], 0.5 * tv[0]);
}

TEST(MotionGtTest, EndpointErrorOfSamples) {
  std::vector<SceneFlowSample> samples = SamplesOf(50, 8);
  MotionGtMetrics exact = EvaluateSamplesGt(samples, TrueVelocity);
  EXPECT_EQ(exact.num_points, 50);
  EXPECT_EQ(exact.epe, 0.0);
  EXPECT_GT(exact.mean_speed, 0.0);
  EXPECT_NEAR(exact.speed_ratio, 1.0, 1e-12);
  // Samples at half speed are off by half the speed.
  for (SceneFlowSample& s : samples) s.v *= 0.5;
  const MotionGtMetrics half = EvaluateSamplesGt(samples, TrueVelocity);
  EXPECT_NEAR(half.rel_epe, 0.5, 1e-12);
  EXPECT_NEAR(half.speed_ratio, 0.5, 1e-12);
  EXPECT_EQ(EvaluateSamplesGt({}, TrueVelocity).num_points, 0);
}

TEST(MotionGtTest, TruthReplacesSampleVelocitiesInFullOrAsSeen) {
  std::vector<SceneFlowSample> samples = SamplesOf(50, 8);
  for (SceneFlowSample& s : samples) {
    s.v = 0.4 * s.v + Eigen::Vector3d(0.1, -0.2, 0.05);
    s.unseen = Eigen::Vector3d(0, 0.6, 0.8);  // a unit line of sight
  }
  samples[7].unseen.setZero();  // a sample that saw every direction
  ASSERT_GT(EvaluateSamplesGt(samples, TrueVelocity).rel_epe, 0.3);

  std::vector<SceneFlowSample> full = samples;
  ReplaceWithTruth(TrueVelocity, TruthPart::kFull, &full);
  for (size_t k = 0; k < full.size(); ++k) {
    EXPECT_EQ(full[k].x, samples[k].x);
    EXPECT_EQ(full[k].v, TrueVelocity(samples[k].x));
    EXPECT_EQ(full[k].unseen, Eigen::Vector3d::Zero());
  }
  EXPECT_EQ(EvaluateSamplesGt(full, TrueVelocity).epe, 0.0);

  std::vector<SceneFlowSample> seen = samples;
  ReplaceWithTruth(TrueVelocity, TruthPart::kSeen, &seen);
  for (size_t k = 0; k < seen.size(); ++k) {
    const Eigen::Vector3d truth = TrueVelocity(samples[k].x);
    EXPECT_EQ(seen[k].unseen, samples[k].unseen);
    // Across the line the truth holds; along it nothing is claimed.
    EXPECT_NEAR(seen[k].v.dot(samples[k].unseen), 0.0, 1e-12) << k;
    const Eigen::Vector3d across =
        truth - truth.dot(samples[k].unseen) * samples[k].unseen;
    EXPECT_LT((seen[k].v - across).norm(), 1e-12) << k;
  }
  EXPECT_EQ(seen[7].v, TrueVelocity(samples[7].x));
}

TEST(MotionGtTest, EndpointErrorOfFittedAndZeroFields) {
  std::vector<Eigen::Vector3d> points;
  for (const SceneFlowSample& s : SamplesOf(400, 6)) points.push_back(s.x);
  MotionField field = SmallField(8, 4, 16);
  std::fill(field.mlp_params().begin(), field.mlp_params().end(), 0.0);
  // V = 0: the error is the true speed itself.
  MotionGtMetrics zero = EvaluateMotionGt(field, points, TrueVelocity);
  EXPECT_EQ(zero.num_points, 400);
  EXPECT_GT(zero.mean_speed, 0.0);
  EXPECT_NEAR(zero.epe, zero.mean_speed, 1e-12);
  EXPECT_NEAR(zero.rel_epe, 1.0, 1e-12);
  EXPECT_EQ(zero.speed_ratio, 0.0);

  FlowPretrainOptions options;
  options.iterations = 300;
  options.batch_size = 500;
  field.Initialize(1);
  PretrainMotionField(SamplesOf(2000, 7), options, &field);
  const MotionGtMetrics fitted = EvaluateMotionGt(field, points, TrueVelocity);
  EXPECT_LT(fitted.rel_epe, 0.1);
  // A constant offset of the truth is measured exactly.
  const MotionGtMetrics shifted =
      EvaluateMotionGt(field, points,
                       [](const Eigen::Vector3d& x) -> Eigen::Vector3d {
                         return TrueVelocity(x) + Eigen::Vector3d(0.3, 0, 0);
                       });
  EXPECT_NEAR(shifted.epe, 0.3, 0.02);

  // Per point: the field's and the truth's velocity, summarized to the
  // same figures, and one CSV row each in the order given.
  const std::vector<MotionGtPoint> per_point =
      MotionGtPoints(field, points, TrueVelocity);
  ASSERT_EQ(per_point.size(), points.size());
  const MotionGtMetrics summary = SummarizeMotionGt(per_point);
  EXPECT_DOUBLE_EQ(summary.epe, fitted.epe);
  EXPECT_DOUBLE_EQ(summary.speed_ratio, fitted.speed_ratio);
  EXPECT_EQ(per_point[5].x, points[5]);
  EXPECT_EQ(per_point[5].truth, TrueVelocity(points[5]));
  const std::string csv = MotionGtCsv(per_point);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 401);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "x,y,z,model_vx,model_vy,model_vz,true_vx,true_vy,true_vz");
}

TEST(FlowPretrainTest, RejectsEmptySamplesAndOversizedLm) {
  MotionField field = SmallField(8, 4, 16);
  EXPECT_THROW(PretrainMotionField({}, FlowPretrainOptions(), &field),
               InputError);
  FlowPretrainOptions options;
  options.solver = PretrainSolver::kLm;
  options.lm_max_jacobian_values = 1000;
  EXPECT_THROW(PretrainMotionField(SamplesOf(10, 1), options, &field),
               InputError);
}

TEST(FlowPretrainTest, ParsesSolverNames) {
  for (PretrainSolver s :
       {PretrainSolver::kAdam, PretrainSolver::kLbfgs, PretrainSolver::kLm}) {
    EXPECT_EQ(ParsePretrainSolver(PretrainSolverName(s)), s);
  }
  EXPECT_THROW(ParsePretrainSolver("sgd"), InputError);
}

}  // namespace
}  // namespace es
