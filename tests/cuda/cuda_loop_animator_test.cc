// The device Alg. 2 animator against its CPU twin, LoopAnimator: after
// Start at a frame (Alg. 1 to each Gaussian's cycle index) and after every
// Advance over two cycles (one Euler step per frame, reset to the
// canonical position where the cycle index wraps), the positions, cycle
// indices and step counts, for a first frame of 0 and one inside the
// cycle, with points outside the box and clamped steps. Double on both
// sides: within 1e-9 relative. Skips when no CUDA device is present.

#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/loop/cuda/device_loop_animator.h"
#include "core/loop/cycle_time.h"
#include "core/loop/loop_animator.h"
#include "core/base/cuda/device_buffer.h"
#include "tests/central_differences.h"
#include "tests/small_motion_field.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

constexpr int kCycle = 6;
constexpr double kTolerance = 1e-9;

class DeviceLoopAnimatorTest : public ::testing::TestWithParam<int> {};

TEST_P(DeviceLoopAnimatorTest, EveryFrameMatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA loop animator");
  MotionField field = SmallMotionField(30, 0.05);
  EulerOptions euler;
  euler.max_step_fraction = 0.01;  // some steps are clamped
  const int n = 14;
  std::vector<double> x0 = Uniform(3 * n, -1.3, 1.3, 31);
  x0[0] = 5.0;  // outside the box
  const std::vector<int> start = RandomStartTimes(n, kCycle, 32);
  const int first_frame = GetParam();

  DeviceMotionField device_field(field);
  DeviceFieldBlocks params;
  params.Upload(field.triplane_params(), field.mlp_params());
  DeviceBuffer<double> dev_x0;
  dev_x0.Upload(x0);
  DeviceLoopAnimator device(&device_field, euler, kCycle);
  device.Start(params.params(), n, dev_x0.data(), start, first_frame);
  LoopAnimator cpu(&field, euler, kCycle);
  cpu.Start(field.params(), n, x0.data(), start, first_frame);
  std::vector<double> positions(3 * n);
  std::vector<int> cycle_index(n);
  for (int frame = first_frame; frame <= first_frame + 2 * kCycle; ++frame) {
    if (frame > first_frame) {
      device.Advance(params.params());
      cpu.Advance(field.params());
    }
    ASSERT_EQ(device.frame(), frame);
    CopyToHost(positions.data(), device.positions(),
               positions.size() * sizeof(double));
    CopyToHost(cycle_index.data(), device.cycle_indices(),
               cycle_index.size() * sizeof(int));
    SCOPED_TRACE("frame " + std::to_string(frame));
    ExpectTwinsNear(positions, cpu.positions(), kTolerance, "positions");
    EXPECT_EQ(cycle_index, cpu.cycle_indices());
    const EulerStats got = device.stats(), want = cpu.stats();
    EXPECT_EQ(got.velocity_evaluations, want.velocity_evaluations);
    EXPECT_EQ(got.clamped_steps, want.clamped_steps);
    EXPECT_EQ(got.nonfinite_velocities, want.nonfinite_velocities);
  }
  EXPECT_GT(cpu.stats().clamped_steps, 0);
}

INSTANTIATE_TEST_SUITE_P(FirstFrames, DeviceLoopAnimatorTest,
                         ::testing::Values(0, 4));

}  // namespace
}  // namespace cuda
}  // namespace es
