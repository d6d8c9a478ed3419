// The device V pretraining (cuda::PretrainMotionFieldOnDevice) against
// the CPU's (PretrainMotionField, Adam): on a tiny field (R = 8, 4
// channels, MLP width 16) and a few dozen samples, the batch loss at every
// step (through the progress callback), the report and the fitted
// parameters; the triplane's total variation (DeviceTriplane::
// TotalVariation), which the fit adds, against Triplane's value and
// gradient; the lbfgs and lm solvers refused; a fit whose loss is never
// finite stopped by the divergence guard on both. Skips when no CUDA
// device is present.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_triplane.h"
#include "core/base/input_error.h"
#include "core/base/cuda/device_buffer.h"
#include "solvers/train/cuda/device_flow_pretrain.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_pretrain.h"
#include "tests/central_differences.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/random_scene_flow_samples.h"
#include "tests/small_motion_field.h"
#include "tests/expect_error.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

std::vector<SceneFlowSample> Samples(int n, uint32_t seed) {
  return RandomSceneFlowSamples(n, seed, 0.95, 0.03);
}

FlowPretrainOptions TinyFit(std::vector<double>* rmse) {
  FlowPretrainOptions o;
  o.iterations = 6;
  o.batch_size = 16;
  o.lr_triplane = 1e-2;
  o.lr_mlp = 1e-3;
  o.tv_weight = 1.0;
  o.seed = 7;
  o.log_every = 1;
  o.progress = [rmse](int, double, double batch_rmse) {
    rmse->push_back(batch_rmse);
  };
  return o;
}

TEST(CudaTotalVariationTest, MatchesTheCpuValueAndGradient) {
  ES_REQUIRE_GPU("triplane total variation");
  MotionField field = SmallMotionField(3);
  const Triplane& triplane = field.triplane();
  const int n = triplane.num_params();
  const double weight = 0.7;
  std::vector<double> want_grad = Uniform(n, -1.0, 1.0, 4);
  const double want =
      triplane.TotalVariation(field.triplane_params().data(), weight,
                              want_grad.data());
  const DeviceTriplane device(triplane);
  DeviceBuffer<double> params, grad, scratch;
  params.Upload(field.triplane_params());
  grad.Upload(Uniform(n, -1.0, 1.0, 4));
  const double got =
      device.TotalVariation(params.data(), weight, grad.data(), &scratch);
  EXPECT_GT(want, 0);
  EXPECT_NEAR(got, want, 1e-13 * want);
  ExpectTwinsNear(grad.Download(), want_grad, 1e-13, "TV gradient");
  // The gradient was added: it is not the starting values alone.
  const std::vector<double> start = Uniform(n, -1.0, 1.0, 4);
  double moved = 0;
  for (int k = 0; k < n; ++k) moved += std::abs(want_grad[k] - start[k]);
  EXPECT_GT(moved, 1e-3);
  // Value alone, no gradient.
  EXPECT_NEAR(device.TotalVariation(params.data(), weight, nullptr, &scratch),
              want, 1e-13 * want);
}

TEST(CudaFlowPretrainTest, AdamStepsMatchTheCpu) {
  ES_REQUIRE_GPU("V pretraining");
  const std::vector<SceneFlowSample> samples = Samples(40, 8);
  std::vector<double> cpu_rmse, device_rmse;
  MotionField cpu_field = SmallMotionField(3);
  MotionField device_field = SmallMotionField(3);
  const FlowPretrainReport want =
      PretrainMotionField(samples, TinyFit(&cpu_rmse), &cpu_field);
  const FlowPretrainReport got = PretrainMotionFieldOnDevice(
      samples, TinyFit(&device_rmse), &device_field);

  ASSERT_EQ(cpu_rmse.size(), 6u);
  ASSERT_EQ(device_rmse.size(), cpu_rmse.size());
  double worst = 0;
  for (size_t k = 0; k < cpu_rmse.size(); ++k) {
    worst = std::max(worst,
                     std::abs(device_rmse[k] - cpu_rmse[k]) / cpu_rmse[k]);
  }
  EXPECT_LT(worst, 1e-9) << "batch rmse per step";
  RecordProperty("worst_step_rmse_error", std::to_string(worst));
  EXPECT_EQ(got.num_samples, want.num_samples);
  EXPECT_EQ(got.iterations, want.iterations);
  EXPECT_NEAR(got.target_rms, want.target_rms, 1e-14 * want.target_rms);
  EXPECT_NEAR(got.initial_rmse, want.initial_rmse, 1e-12 * want.initial_rmse);
  EXPECT_NEAR(got.fit_rmse, want.fit_rmse, 1e-9 * want.fit_rmse);
  // The fit did something, so the comparison is not of two starts.
  EXPECT_LT(want.fit_rmse, 0.9 * want.initial_rmse);
  ExpectTwinsNear(device_field.triplane_params(), cpu_field.triplane_params(),
                  1e-9, "triplane parameters");
  ExpectTwinsNear(device_field.mlp_params(), cpu_field.mlp_params(), 1e-9,
                  "MLP parameters");
}

TEST(CudaFlowPretrainTest, RefusesTheCeresSolversAndNoSamples) {
  ES_REQUIRE_GPU("V pretraining");
  std::vector<double> rmse;
  MotionField field = SmallMotionField(3);
  for (PretrainSolver solver : {PretrainSolver::kLbfgs, PretrainSolver::kLm}) {
    FlowPretrainOptions o = TinyFit(&rmse);
    o.solver = solver;
    EXPECT_THROW(PretrainMotionFieldOnDevice(Samples(4, 1), o, &field),
                 InputError);
  }
  EXPECT_THROW(PretrainMotionFieldOnDevice({}, TinyFit(&rmse), &field),
               InputError);
  EXPECT_TRUE(rmse.empty());
}

TEST(CudaFlowPretrainTest, NonFiniteLossesStopBothFits) {
  ES_REQUIRE_GPU("V pretraining");
  std::vector<SceneFlowSample> samples = Samples(4, 2);
  for (SceneFlowSample& s : samples) s.v.x() = std::nan("");
  std::vector<double> rmse;
  FlowPretrainOptions o = TinyFit(&rmse);
  o.batch_size = 2;
  o.max_nonfinite_steps = 3;
  MotionField cpu_field = SmallMotionField(3);
  MotionField device_field = SmallMotionField(3);
  EXPECT_THROW(PretrainMotionField(samples, o, &cpu_field), TrainingDiverged);
  EXPECT_THROW(PretrainMotionFieldOnDevice(samples, o, &device_field),
               TrainingDiverged);
  EXPECT_TRUE(rmse.empty()) << "a skipped step reported progress";
}

// --lr_mlp 1e30 (fit RMSE 5.7e60, exit 0 before) stops both fits at the
// first step, naming the flag.
TEST(CudaFlowPretrainTest, RunawayLearningRateStopsBothFits) {
  ES_REQUIRE_GPU("V pretraining");
  const std::vector<SceneFlowSample> samples = Samples(40, 2);
  std::vector<double> rmse;
  FlowPretrainOptions o = TinyFit(&rmse);
  o.lr_mlp = 1e30;
  MotionField cpu_field = SmallMotionField(3);
  MotionField device_field = SmallMotionField(3);
  ExpectErrorNaming<TrainingDiverged>(
      [&] { PretrainMotionField(samples, o, &cpu_field); }, {"--lr_mlp 1e+30"});
  ExpectErrorNaming<TrainingDiverged>(
      [&] { PretrainMotionFieldOnDevice(samples, o, &device_field); },
      {"--lr_mlp 1e+30"});
  EXPECT_TRUE(rmse.empty()) << "a stopped step reported progress";
}

}  // namespace
}  // namespace cuda
}  // namespace es
