#include "core/loop/cycle_time.h"
#include "core/loop/euler_chain.h"
#include "core/loop/loop_animator.h"

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/central_differences.h"
#include "tests/small_motion_field.h"

namespace es {
namespace {

using central_differences::ExpectGradientsNear;
using central_differences::Uniform;

constexpr int kCycle = 15;

// The obviously-correct twin of EulerChain::Forward: one point at a time,
// one step at a time, with the stress rule written out.
std::vector<double> ReferenceAdvect(const MotionField& field,
                                    const std::vector<double>& x0,
                                    const std::vector<int>& steps,
                                    double max_step) {
  std::vector<double> x = x0;
  FieldWorkspace ws;
  for (size_t k = 0; k < steps.size(); ++k) {
    for (int s = 0; s < steps[k]; ++s) {
      Eigen::Vector3d v;
      field.Evaluate(field.params(), 1, &x[3 * k], v.data(), &ws);
      if (!v.allFinite()) v.setZero();
      if (v.norm() > max_step) v *= max_step / v.norm();
      for (int j = 0; j < 3; ++j) x[3 * k + j] += v[j];
    }
  }
  return x;
}

TEST(CycleTest, IndexAndNumberHandleNegativeOffsets) {
  EXPECT_EQ(CycleIndex(0, 3, 15), 12);
  EXPECT_EQ(CycleNumber(0, 3, 15), -1);
  EXPECT_EQ(CycleIndex(3, 3, 15), 0);
  EXPECT_EQ(CycleNumber(3, 3, 15), 0);
  EXPECT_EQ(CycleIndex(17, 3, 15), 14);
  EXPECT_EQ(CycleNumber(18, 3, 15), 1);
  EXPECT_EQ(CycleIndex(-16, 0, 15), 14);
  EXPECT_EQ(CycleNumber(-16, 0, 15), -2);
  EXPECT_EQ(CycleNumber(-15, 0, 15), -1);
  for (int t0 = 0; t0 < 15; ++t0) {
    for (int i = -40; i < 60; ++i) {
      const int t = CycleIndex(i, t0, 15);
      const int p = CycleNumber(i, t0, 15);
      EXPECT_GE(t, 0);
      EXPECT_LT(t, 15);
      EXPECT_EQ(t0 + p * 15 + t, i);
    }
  }
}

TEST(CycleTest, RandomStartTimesAreSeededAndInRange) {
  const std::vector<int> a = RandomStartTimes(1000, kCycle, 5);
  EXPECT_EQ(a, RandomStartTimes(1000, kCycle, 5));
  EXPECT_NE(a, RandomStartTimes(1000, kCycle, 6));
  std::vector<int> histogram(kCycle, 0);
  for (int t : a) {
    ASSERT_GE(t, 0);
    ASSERT_LT(t, kCycle);
    ++histogram[t];
  }
  for (int count : histogram) EXPECT_GT(count, 0);
}

TEST(EulerChainTest, ForwardMatchesOnePointAtATime) {
  const MotionField field = SmallMotionField(1);
  const int n = 40;
  const std::vector<double> x0 = Uniform(3 * n, -1.2, 1.2, 2);
  std::vector<int> steps = RandomStartTimes(n, kCycle + 1, 3);
  EulerChain chain(&field, EulerOptions());
  std::vector<double> x(3 * n);
  chain.Forward(field.params(), n, x0.data(), steps.data(), x.data());
  const std::vector<double> expected =
      ReferenceAdvect(field, x0, steps, chain.max_step());
  double moved = 0.0;
  for (int i = 0; i < 3 * n; ++i) {
    EXPECT_NEAR(x[i], expected[i], 1e-12);
    moved = std::max(moved, std::abs(x[i] - x0[i]));
  }
  EXPECT_GT(moved, 1e-2);
  int total_steps = 0;
  for (int s : steps) total_steps += s;
  EXPECT_EQ(chain.stats().velocity_evaluations, total_steps);
  EXPECT_EQ(chain.stats().clamped_steps, 0);
}

// Gradients of sum(w * X_final) through up to L steps.
void CheckChainGradients(const EulerOptions& options, bool expect_clamps) {
  MotionField field = SmallMotionField(4);
  const int n = 12;
  std::vector<double> x0 = Uniform(3 * n, -1.2, 1.2, 5);
  std::vector<int> steps = RandomStartTimes(n, kCycle, 6);
  steps[0] = kCycle;
  steps[1] = 0;
  const std::vector<double> weights = Uniform(3 * n, -1.0, 1.0, 7);
  EulerChain chain(&field, options);
  std::vector<double> x(3 * n);
  auto loss = [&]() {
    chain.Forward(field.params(), n, x0.data(), steps.data(), x.data());
    double sum = 0.0;
    for (int i = 0; i < 3 * n; ++i) sum += weights[i] * x[i];
    return sum;
  };
  loss();
  EXPECT_EQ(chain.stats().clamped_steps > 0, expect_clamps);
  std::vector<double> d_triplane(field.triplane_params().size(), 0.0);
  std::vector<double> d_mlp(field.mlp_params().size(), 0.0);
  std::vector<double> d_x0(3 * n, 0.0);
  chain.Backward(field.params(), weights.data(),
                 {d_triplane.data(), d_mlp.data()}, d_x0.data());
  ExpectGradientsNear(d_triplane, loss, &field.triplane_params(), "triplane");
  ExpectGradientsNear(d_mlp, loss, &field.mlp_params(), "mlp");
  ExpectGradientsNear(d_x0, loss, &x0, "x0");
  // A point that takes no step passes its gradient straight through.
  for (int j = 0; j < 3; ++j) EXPECT_EQ(d_x0[3 + j], weights[3 + j]);
}

TEST(EulerChainTest, GradientsOverAFullCycleMatchCentralDifferences) {
  CheckChainGradients(EulerOptions(), false);
}

TEST(EulerChainTest, GradientsThroughClampedStepsMatchCentralDifferences) {
  EulerOptions options;
  options.max_step_fraction = 0.005;
  CheckChainGradients(options, true);
}

// Past its memory budget the chain drops the later steps' activations and
// evaluates V again in Backward: the gradients stay right and equal to
// those from kept activations.
TEST(EulerChainTest, DroppedActivationsGiveTheSameGradients) {
  EulerOptions small;
  small.max_kept_activation_bytes = 8192;  // a few of the first steps
  CheckChainGradients(small, false);
  MotionField field = SmallMotionField(10);
  const int n = 30;
  const std::vector<double> x0 = Uniform(3 * n, -1.2, 1.2, 11);
  const std::vector<int> steps = RandomStartTimes(n, kCycle, 12);
  const std::vector<double> d_x = Uniform(3 * n, -1.0, 1.0, 13);
  auto gradients = [&](const EulerOptions& options) {
    EulerChain chain(&field, options);
    std::vector<double> x(3 * n);
    std::vector<double> d(field.triplane_params().size() +
                              field.mlp_params().size() + 3 * n,
                          0.0);
    chain.Forward(field.params(), n, x0.data(), steps.data(), x.data());
    double* d_mlp = d.data() + field.triplane_params().size();
    chain.Backward(field.params(), d_x.data(), {d.data(), d_mlp},
                   d_mlp + field.mlp_params().size());
    return d;
  };
  EulerOptions none;
  none.max_kept_activation_bytes = 0;
  EXPECT_EQ(gradients(none), gradients(EulerOptions()));
  EXPECT_EQ(gradients(small), gradients(EulerOptions()));
}

TEST(LoopAnimatorTest, ReproducesEulerChainForEveryFrame) {
  const MotionField field = SmallMotionField(8);
  const int n = 300;
  const std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 9);
  const std::vector<int> start = RandomStartTimes(n, kCycle, 10);
  for (const int first_frame : {0, 7}) {
    LoopAnimator animator(&field, EulerOptions(), kCycle);
    animator.Start(field.params(), n, x0.data(), start, first_frame);
    EulerChain chain(&field, EulerOptions());
    std::vector<int> steps(n);
    std::vector<double> expected(3 * n);
    std::vector<std::vector<double>> history;
    const int frames = 4 * kCycle;
    for (int i = first_frame; i < first_frame + frames; ++i) {
      if (i > first_frame) animator.Advance(field.params());
      ASSERT_EQ(animator.frame(), i);
      for (int k = 0; k < n; ++k) steps[k] = CycleIndex(i, start[k], kCycle);
      ASSERT_EQ(animator.cycle_indices(), steps);
      chain.Forward(field.params(), n, x0.data(), steps.data(),
                    expected.data());
      const std::vector<double>& x = animator.positions();
      for (int c = 0; c < 3 * n; ++c) {
        ASSERT_NEAR(x[c], expected[c], 1e-12) << "frame " << i;
      }
      history.push_back(x);
    }
    // Periodic: frame i and i + L agree; bit for bit once every Gaussian
    // has wrapped (before that, positions came from Alg. 1's batches).
    for (int f = 0; f + kCycle < frames; ++f) {
      if (f >= kCycle) {
        ASSERT_EQ(history[f], history[f + kCycle]) << "frame " << f;
      }
      for (int c = 0; c < 3 * n; ++c) {
        ASSERT_NEAR(history[f][c], history[f + kCycle][c], 1e-12);
      }
    }
    EXPECT_EQ(animator.stats().nonfinite_velocities, 0);
  }
}

TEST(EulerStressTest, NanVelocitiesAreZeroedAndCounted) {
  MotionField field = SmallMotionField(11);
  // A NaN output bias makes every velocity NaN.
  field.mlp_params().back() = std::numeric_limits<double>::quiet_NaN();
  const int n = 20;
  const std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 12);
  std::vector<int> steps(n, 5);
  EulerChain chain(&field, EulerOptions());
  std::vector<double> x(3 * n);
  chain.Forward(field.params(), n, x0.data(), steps.data(), x.data());
  EXPECT_EQ(x, x0);
  EXPECT_EQ(chain.stats().nonfinite_velocities, 5 * n);

  LoopAnimator animator(&field, EulerOptions(), kCycle);
  animator.Start(field.params(), n, x0.data(), RandomStartTimes(n, kCycle, 13),
                 0);
  for (int i = 0; i < 20; ++i) animator.Advance(field.params());
  for (double c : animator.positions()) EXPECT_TRUE(std::isfinite(c));
  EXPECT_GT(animator.stats().nonfinite_velocities, 0);
}

TEST(EulerStressTest, HugeVelocitiesAreClampedAndStayFinite) {
  MotionField field = OverflowingMotionField(14);
  const int n = 20;
  std::vector<double> x0 = Uniform(3 * n, -1.0, 1.0, 15);
  x0[0] = 1e300;  // far outside the box: the triplane clamps
  x0[4] = -std::numeric_limits<double>::infinity();
  std::vector<int> steps(n, kCycle - 1);
  EulerChain chain(&field, EulerOptions());
  std::vector<double> x(3 * n);
  chain.Forward(field.params(), n, x0.data(), steps.data(), x.data());
  for (int i = 0; i < 3 * n; ++i) {
    EXPECT_FALSE(std::isnan(x[i])) << i;
    if (std::isfinite(x0[i])) {
      EXPECT_TRUE(std::isfinite(x[i])) << i;
      // Never more than max_step per step.
      EXPECT_LE(std::abs(x[i] - x0[i]), (kCycle - 1) * chain.max_step());
    }
  }
  const EulerStats& stats = chain.stats();
  EXPECT_EQ(stats.clamped_steps + stats.nonfinite_velocities,
            stats.velocity_evaluations);
  EXPECT_GT(stats.clamped_steps, 0);

  std::vector<double> d_mlp(field.mlp_params().size(), 0.0);
  std::vector<double> d_x0(3 * n, 0.0);
  const std::vector<double> ones(3 * n, 1.0);
  chain.Backward(field.params(), ones.data(), {nullptr, d_mlp.data()},
                 d_x0.data());
  for (double g : d_x0) EXPECT_FALSE(std::isnan(g));
}

}  // namespace
}  // namespace es
