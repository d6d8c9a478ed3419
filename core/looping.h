#ifndef EULERSPLAT_CORE_LOOPING_H_
#define EULERSPLAT_CORE_LOOPING_H_

#include <cstdint>
#include <vector>

#include "core/motion_field.h"

namespace es {

// Looping time. Dynamic Gaussian n starts its loop at frame t0_n in [0, L).
// At frame i it is at cycle index t = (i - t0_n) mod L, always in [0, L)
// even for i < t0_n, in cycle number p = floor((i - t0_n) / L), negative
// for i < t0_n.
int CycleIndex(int frame, int start_time, int cycle_length);
int CycleNumber(int frame, int start_time, int cycle_length);
// n start times uniform in [0, cycle_length), from std::mt19937(seed).
std::vector<int> RandomStartTimes(int n, int cycle_length, uint32_t seed);

// Numerical stress rule of the Euler chain. Every step evaluates
// v = V(x); if any component of v is not finite the step is v = 0 (counted
// in nonfinite_velocities); else if |v| > max_step the step is
// v * max_step / |v| (counted in clamped_steps). So positions stay finite
// whatever the field outputs, and the gradient through a step is that of
// this clamped (scaled) function, zero for a non-finite one. A non-finite
// canonical position keeps its kind: the triplane clamps it, the step is
// finite, so +-Inf stays +-Inf and NaN stays NaN.
struct EulerOptions {
  // max_step = max_step_fraction * the motion field's box diagonal.
  double max_step_fraction = 0.25;
};

struct EulerStats {
  int64_t velocity_evaluations = 0;
  int64_t nonfinite_velocities = 0;
  int64_t clamped_steps = 0;
};

// Alg. 1: advects canonical positions x0 by forward Euler, X <- X + V(X),
// steps[k] times for point k. All points move in lockstep in one batch per
// step; points whose count is reached drop out (they are kept sorted by
// step count so the active ones are a prefix). The trajectory is stored so
// Backward can run reverse mode through the chain; V is re-evaluated there
// rather than storing its activations (memory O(sum of steps) doubles).
// Only the points given (the dynamic Gaussians) are processed.
class EulerChain {
 public:
  EulerChain(const MotionField* field, const EulerOptions& options);

  // x_out (n x 3) = x0 (n x 3) advected steps[k] >= 0 times. Keeps the
  // trajectory for Backward; x0 is copied.
  void Forward(const FieldParams& params, int n, const double* x0,
               const int* steps, double* x_out);
  // Given d_x_out (n x 3) for the last Forward (same params), accumulates
  // V's parameter gradients into grads and dL/dx0 into d_x0 (n x 3,
  // nullable).
  void Backward(const FieldParams& params, const double* d_x_out,
                const FieldGradients& grads, double* d_x0);

  // Counts of the last Forward.
  const EulerStats& stats() const { return stats_; }
  double max_step() const;

 private:
  const MotionField* field_;
  EulerOptions options_;
  EulerStats stats_;
  int n_ = 0;
  std::vector<int> order_;      // sorted position -> caller's index
  std::vector<int> active_;     // active_[s] = points with more than s steps
  std::vector<size_t> offset_;  // trajectory_ offset of step s positions
  std::vector<double> trajectory_;  // x_s of the active points, s = 0 ..
  std::vector<double> velocity_, gradient_, step_gradient_, d_x_;
  FieldWorkspace workspace_;
};

// Alg. 2: looping animation at O(N) per frame. Start() places every
// Gaussian at its cycle index for a frame (Alg. 1, O(N L) once); Advance()
// then takes one Euler step per Gaussian per frame, resetting a Gaussian to
// its canonical position when its cycle index wraps from L - 1 to 0. The
// cycle number p is 0 at inference, so the animation has period L exactly.
class LoopAnimator {
 public:
  LoopAnimator(const MotionField* field, const EulerOptions& options,
               int cycle_length);

  // x0 (n x 3) is copied; start_times has n entries in [0, L).
  void Start(const FieldParams& params, int n, const double* x0,
             const std::vector<int>& start_times, int frame);
  void Advance(const FieldParams& params);

  int frame() const { return frame_; }
  // n x 3, in the order of x0.
  const std::vector<double>& positions() const { return positions_; }
  const std::vector<int>& cycle_indices() const { return cycle_index_; }
  // Accumulated since Start().
  const EulerStats& stats() const { return stats_; }

 private:
  const MotionField* field_;
  int cycle_length_;
  int frame_ = 0;
  std::vector<double> canonical_, positions_, velocity_;
  std::vector<int> cycle_index_;
  EulerChain chain_;
  EulerStats stats_;
  FieldWorkspace workspace_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOPING_H_
