// The device scene-flow prior against its CPU twin (SceneFlowPrior): over
// several iterations of a run, so that the batches (drawn from the same
// seed and iteration) and the decaying weight must match, the loss and
// V's triplane and MLP gradients, added (+=) to non-zero arrays as on the
// CPU; a batch as large as the samples; no gradient wanted; the prior
// off. Double on both sides, summed in another order: within 1e-10
// relative. Skips when no CUDA device is present.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "costs/cuda/device_scene_flow_prior.h"
#include "costs/scene_flow_prior.h"
#include "tests/central_differences.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/random_scene_flow_samples.h"
#include "tests/small_motion_field.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

constexpr double kTolerance = 1e-10;

std::vector<SceneFlowSample> Samples(int n, uint32_t seed) {
  return RandomSceneFlowSamples(n, seed, 0.95, 0.03);
}

// Runs `iterations` of each prior, from the same non-zero gradients,
// comparing the loss at each and the accumulated gradients at the end.
void ExpectTwinsOverRun(const FlowPriorOptions& options, int num_samples,
                        int iterations) {
  const MotionField field = SmallMotionField(3);
  const std::vector<SceneFlowSample> samples = Samples(num_samples, 8);
  SceneFlowPrior cpu(&field, samples, options);
  const DeviceMotionField device_field(field);
  DeviceSceneFlowPrior device(&device_field, samples, options);
  EXPECT_EQ(device.num_samples(), cpu.num_samples());

  const int triplane_size = field.triplane().num_params();
  const int mlp_size = field.mlp().num_params();
  std::vector<double> grad_triplane = Uniform(triplane_size, -1.0, 1.0, 4);
  std::vector<double> grad_mlp = Uniform(mlp_size, -1.0, 1.0, 5);
  DeviceFieldBlocks params, grads;
  params.Upload(field.params(), triplane_size, mlp_size);
  grads.Upload(grad_triplane, grad_mlp);
  const uint64_t seed = 0x123456789abcULL;
  for (int it = 0; it < iterations; ++it) {
    EXPECT_EQ(device.Weight(it, iterations), cpu.Weight(it, iterations));
    const double want = cpu.AddLossAndGradient(
        field.params(), it, iterations, seed,
        {grad_triplane.data(), grad_mlp.data()});
    const double got = device.AddLossAndGradient(params.params(), it,
                                                 iterations, seed,
                                                 grads.gradients());
    EXPECT_GT(want, 0);
    EXPECT_NEAR(got, want, kTolerance * want) << "iteration " << it;
  }
  ExpectFieldGradientsNear(grads, grad_triplane, grad_mlp, kTolerance);
  // Not the starting values alone: the run added to them.
  const std::vector<double> start = Uniform(mlp_size, -1.0, 1.0, 5);
  double moved = 0;
  for (int k = 0; k < mlp_size; ++k)
    moved = std::max(moved, std::abs(grad_mlp[k] - start[k]));
  EXPECT_GT(moved, 1e-6);
}

TEST(DeviceSceneFlowPrior, MatchesCpuTwinOverARun) {
  ES_REQUIRE_GPU("CUDA scene-flow prior");
  FlowPriorOptions options;
  options.weight = 0.8;
  options.final_factor = 0.05;
  options.batch_size = 40;
  ExpectTwinsOverRun(options, 300, 3);
}

// batch_size above the sample count: every batch holds num_samples draws.
TEST(DeviceSceneFlowPrior, BatchLargerThanTheSamples) {
  ES_REQUIRE_GPU("CUDA scene-flow prior");
  FlowPriorOptions options;
  options.weight = 1.5;
  options.batch_size = 1024;
  ExpectTwinsOverRun(options, 30, 2);
}

// No gradient blocks: the same loss, nothing written; weight 0: 0.
TEST(DeviceSceneFlowPrior, LossAloneAndOff) {
  ES_REQUIRE_GPU("CUDA scene-flow prior");
  const MotionField field = SmallMotionField(4);
  const std::vector<SceneFlowSample> samples = Samples(50, 9);
  FlowPriorOptions options;
  options.weight = 0.3;
  options.batch_size = 20;
  SceneFlowPrior cpu(&field, samples, options);
  const DeviceMotionField device_field(field);
  DeviceSceneFlowPrior device(&device_field, samples, options);
  DeviceFieldBlocks params;
  params.Upload(field.params(), field.triplane().num_params(),
                field.mlp().num_params());
  const double want = cpu.AddLossAndGradient(field.params(), 2, 10, 7, {});
  EXPECT_NEAR(device.AddLossAndGradient(params.params(), 2, 10, 7, {}), want,
              kTolerance * want);
  options.weight = 0;
  DeviceSceneFlowPrior off(&device_field, samples, options);
  EXPECT_EQ(off.AddLossAndGradient(params.params(), 2, 10, 7, {}), 0.0);
}

}  // namespace
}  // namespace cuda
}  // namespace es
