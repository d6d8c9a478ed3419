// The device Euler chain (Alg. 1) against its CPU twin, EulerChain: final
// positions, the stress counts, and the gradients to V's parameters and to
// x0, for per-point step counts (a full cycle, zero steps), clamped steps,
// activations dropped for memory and evaluated again, many steps, and the
// stress cases of the CPU tests (NaN velocities, overflowing velocities,
// non-finite and far-away positions). Double on both sides, summed in
// another order: within 1e-9 relative. Skips when no CUDA device is
// present.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/loop/cuda/device_euler_chain.h"
#include "core/loop/cycle_time.h"
#include "core/loop/euler_chain.h"
#include "core/base/cuda/device_buffer.h"
#include "tests/central_differences.h"
#include "tests/small_motion_field.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

constexpr int kCycle = 15;
constexpr double kTolerance = 1e-9;

// One chain's outputs: final positions, counts, gradients.
struct ChainResult {
  std::vector<double> x, d_triplane, d_mlp, d_x0;
  EulerStats stats;
};

// The CPU chain: Forward, then Backward of sum(d_x_out . x) into gradients
// that start at `start` (accumulation is part of the contract).
ChainResult CpuChain(const MotionField& field, const EulerOptions& options,
                     const std::vector<double>& x0,
                     const std::vector<int>& steps,
                     const std::vector<double>& d_x_out,
                     const std::vector<double>& d_x0_start) {
  const int n = static_cast<int>(steps.size());
  ChainResult r;
  r.x.resize(3 * n);
  r.d_triplane.assign(field.triplane().num_params(), 0.5);
  r.d_mlp.assign(field.mlp().num_params(), -0.25);
  r.d_x0 = d_x0_start;
  EulerChain chain(&field, options);
  chain.Forward(field.params(), n, x0.data(), steps.data(), r.x.data());
  chain.Backward(field.params(), d_x_out.data(),
                 {r.d_triplane.data(), r.d_mlp.data()}, r.d_x0.data());
  r.stats = chain.stats();
  return r;
}

ChainResult DeviceChain(const MotionField& field, const EulerOptions& options,
                        const std::vector<double>& x0,
                        const std::vector<int>& steps,
                        const std::vector<double>& d_x_out,
                        const std::vector<double>& d_x0_start) {
  const int n = static_cast<int>(steps.size());
  DeviceMotionField device(field);
  DeviceFieldBlocks params, grads;
  params.Upload(field.params(), field.triplane().num_params(),
                field.mlp().num_params());
  grads.Upload(std::vector<double>(field.triplane().num_params(), 0.5),
               std::vector<double>(field.mlp().num_params(), -0.25));
  DeviceBuffer<double> dev_x0, dev_x(3 * n), dev_d_x_out, dev_d_x0;
  dev_x0.Upload(x0);
  dev_d_x_out.Upload(d_x_out);
  dev_d_x0.Upload(d_x0_start);
  DeviceEulerChain chain(&device, options);
  EXPECT_EQ(chain.max_step(), EulerChain(&field, options).max_step());
  chain.Forward(params.params(), n, dev_x0.data(), steps.data(),
                dev_x.data());
  chain.Backward(params.params(), dev_d_x_out.data(), grads.gradients(),
                 dev_d_x0.data());
  ChainResult r;
  r.x = dev_x.Download();
  r.d_triplane = grads.triplane.Download();
  r.d_mlp = grads.mlp.Download();
  r.d_x0 = dev_d_x0.Download();
  r.stats = chain.stats();
  return r;
}

void ExpectSameStats(const EulerStats& got, const EulerStats& want) {
  EXPECT_EQ(got.velocity_evaluations, want.velocity_evaluations);
  EXPECT_EQ(got.clamped_steps, want.clamped_steps);
  EXPECT_EQ(got.nonfinite_velocities, want.nonfinite_velocities);
}

void ExpectSameChain(const ChainResult& got, const ChainResult& want) {
  ExpectSameStats(got.stats, want.stats);
  ExpectTwinsNear(got.x, want.x, kTolerance, "x");
  ExpectTwinsNear(got.d_triplane, want.d_triplane, kTolerance, "d_triplane");
  ExpectTwinsNear(got.d_mlp, want.d_mlp, kTolerance, "d_mlp");
  ExpectTwinsNear(got.d_x0, want.d_x0, kTolerance, "d_x0");
}

struct ChainCase {
  const char* name;
  double max_step_fraction;
  size_t kept_bytes;
  bool expect_clamps;
};

class DeviceEulerChainTest : public ::testing::TestWithParam<ChainCase> {};

// Random points (two non-finite, one outside the box, one without steps)
// over up to a full cycle.
TEST_P(DeviceEulerChainTest, MatchesCpuTwin) {
  ES_REQUIRE_GPU("CUDA Euler chain");
  const ChainCase c = GetParam();
  EulerOptions options;
  options.max_step_fraction = c.max_step_fraction;
  options.max_kept_activation_bytes = c.kept_bytes;
  const MotionField field = SmallMotionField(4);
  const int n = 20;
  std::vector<double> x0 = Uniform(3 * n, -1.2, 1.2, 5);
  x0[6] = std::numeric_limits<double>::quiet_NaN();
  x0[10] = -std::numeric_limits<double>::infinity();
  x0[12] = 40.0;
  std::vector<int> steps = RandomStartTimes(n, kCycle, 6);
  steps[0] = kCycle;
  steps[1] = 0;
  const std::vector<double> d_x_out = Uniform(3 * n, -1.0, 1.0, 7);
  const std::vector<double> d_x0_start = Uniform(3 * n, -1.0, 1.0, 8);
  const ChainResult want =
      CpuChain(field, options, x0, steps, d_x_out, d_x0_start);
  const ChainResult got =
      DeviceChain(field, options, x0, steps, d_x_out, d_x0_start);
  EXPECT_EQ(want.stats.clamped_steps > 0, c.expect_clamps);
  ExpectSameChain(got, want);
  // A point that takes no step passes its gradient straight through.
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(got.d_x0[3 + j], d_x0_start[3 + j] + d_x_out[3 + j]);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DeviceEulerChainTest,
    ::testing::Values(ChainCase{"FullCycle", 0.25, size_t{256} << 20, false},
                      ChainCase{"ClampedSteps", 0.005, size_t{256} << 20,
                                true},
                      // A few steps' activations kept, the rest evaluated
                      // again in Backward.
                      ChainCase{"DroppedActivations", 0.25, 8192, false}),
    [](const auto& info) { return std::string(info.param.name); });

// A few points over two cycles.
TEST(DeviceEulerChain, ManyStepsMatchCpuTwin) {
  ES_REQUIRE_GPU("CUDA Euler chain");
  const MotionField field = SmallMotionField(9);
  const int n = 5;
  const std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 10);
  const std::vector<int> steps = {2 * kCycle, kCycle + 1, 7, 2 * kCycle, 1};
  const std::vector<double> d_x_out = Uniform(3 * n, -1.0, 1.0, 11);
  const std::vector<double> zeros(3 * n, 0.0);
  const ChainResult want =
      CpuChain(field, EulerOptions(), x0, steps, d_x_out, zeros);
  const ChainResult got =
      DeviceChain(field, EulerOptions(), x0, steps, d_x_out, zeros);
  ExpectSameChain(got, want);
  EXPECT_EQ(got.stats.velocity_evaluations, 5 * kCycle + 9);
}

// No point steps: positions and gradients pass through, V's gradients
// are left as they were.
TEST(DeviceEulerChain, ZeroStepsPassThrough) {
  ES_REQUIRE_GPU("CUDA Euler chain");
  const MotionField field = SmallMotionField(12);
  const int n = 7;
  const std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 13);
  const std::vector<double> d_x_out = Uniform(3 * n, -1.0, 1.0, 14);
  const std::vector<double> zeros(3 * n, 0.0);
  const ChainResult got = DeviceChain(field, EulerOptions(), x0,
                                      std::vector<int>(n, 0), d_x_out, zeros);
  EXPECT_EQ(got.x, x0);
  EXPECT_EQ(got.d_x0, d_x_out);
  EXPECT_EQ(got.stats.velocity_evaluations, 0);
  for (double g : got.d_triplane) ASSERT_EQ(g, 0.5);
  for (double g : got.d_mlp) ASSERT_EQ(g, -0.25);
}

// A NaN output bias makes every velocity NaN: no point moves, every step
// is counted, the gradients are the CPU's.
TEST(DeviceEulerChain, NanVelocitiesAreZeroedAndCounted) {
  ES_REQUIRE_GPU("CUDA Euler chain");
  MotionField field = SmallMotionField(11);
  field.mlp_params().back() = std::numeric_limits<double>::quiet_NaN();
  const int n = 12;
  const std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 12);
  const std::vector<int> steps(n, 5);
  const std::vector<double> d_x_out = Uniform(3 * n, -1.0, 1.0, 13);
  const std::vector<double> zeros(3 * n, 0.0);
  const ChainResult want =
      CpuChain(field, EulerOptions(), x0, steps, d_x_out, zeros);
  const ChainResult got =
      DeviceChain(field, EulerOptions(), x0, steps, d_x_out, zeros);
  EXPECT_EQ(got.x, x0);
  EXPECT_EQ(got.stats.nonfinite_velocities, 5 * n);
  ExpectSameChain(got, want);
}

// Output weights near 1e300: velocities overflow or are enormous, every
// step is clamped or zeroed, positions stay finite (bar the canonical
// infinity) and move at most max_step a step; no NaN in the gradients.
// Overflow depends on the order of the sums, so only the properties are
// compared with the CPU's.
TEST(DeviceEulerChain, HugeVelocitiesAreClampedAndStayFinite) {
  ES_REQUIRE_GPU("CUDA Euler chain");
  MotionField field = OverflowingMotionField(14);
  const int n = 12;
  std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 15);
  x0[0] = 1e300;  // far outside the box: the triplane clamps
  x0[4] = -std::numeric_limits<double>::infinity();
  const std::vector<int> steps(n, 6);
  const std::vector<double> ones(3 * n, 1.0);
  const std::vector<double> zeros(3 * n, 0.0);
  const ChainResult got =
      DeviceChain(field, EulerOptions(), x0, steps, ones, zeros);
  const ChainResult want =
      CpuChain(field, EulerOptions(), x0, steps, ones, zeros);
  const double max_step = EulerChain(&field, EulerOptions()).max_step();
  for (int i = 0; i < 3 * n; ++i) {
    EXPECT_FALSE(std::isnan(got.x[i])) << i;
    if (std::isfinite(x0[i])) {
      EXPECT_TRUE(std::isfinite(got.x[i])) << i;
      EXPECT_LE(std::abs(got.x[i] - x0[i]), 6 * max_step * (1 + 1e-12)) << i;
    } else {
      EXPECT_EQ(got.x[i], x0[i]) << i;
    }
  }
  EXPECT_EQ(got.stats.velocity_evaluations, want.stats.velocity_evaluations);
  EXPECT_EQ(got.stats.clamped_steps + got.stats.nonfinite_velocities,
            got.stats.velocity_evaluations);
  EXPECT_GT(got.stats.clamped_steps, 0);
  for (double g : got.d_x0) EXPECT_FALSE(std::isnan(g));
}

}  // namespace
}  // namespace cuda
}  // namespace es
