#ifndef EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_
#define EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/fields/motion_field.h"

namespace es {

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
  // Memory EulerChain may spend on keeping V's activations for Backward.
  size_t max_kept_activation_bytes = size_t{256} << 20;
};

struct EulerStats {
  int64_t velocity_evaluations = 0;
  int64_t nonfinite_velocities = 0;
  int64_t clamped_steps = 0;
};

// The batch layout of one Forward, shared by EulerChain and its device
// twin: points sorted by step count, largest first, so the points still
// moving at step s are a prefix.
struct EulerSchedule {
  int max_steps = 0;
  std::vector<int> order;      // sorted position -> caller's index
  std::vector<int> active;     // active[s] = points with more than s steps
  std::vector<size_t> offset;  // trajectory offset of step s positions
  int kept_steps = 0;  // leading steps whose activations fit the budget
};

// The schedule of n points taking steps[k] >= 0 steps, keeping V's
// activations (activation_bytes_per_point each: ActivationBytesPerPoint)
// of the leading steps within max_kept_bytes.
EulerSchedule ScheduleEulerSteps(int n, const int* steps,
                                 size_t activation_bytes_per_point,
                                 size_t max_kept_bytes);

// What one evaluation of an MLP of these sizes keeps in its workspace,
// forward and backward: the features and their gradient, three
// width-sized rows per hidden layer, the output gradient.
size_t ActivationBytesPerPoint(int input_dim, int width, int depth,
                               int output_dim);

// Adds to x the step that the stress rule above takes for velocity v, and
// counts a clamped or non-finite step in stats.
void TakeSafeStep(const double* v, double max_step, double* x,
                  EulerStats* stats);

// Alg. 1: advects canonical positions x0 by forward Euler, X <- X + V(X),
// steps[k] times for point k. All points move in lockstep in one batch per
// step; points whose count is reached drop out (they are kept sorted by
// step count so the active ones are a prefix). The trajectory, velocities
// and V's activations of every step are kept so Backward can run reverse
// mode through the chain without evaluating V again; past
// EulerOptions::max_kept_activation_bytes of activations the later steps'
// are dropped and recomputed in Backward instead (same values). Only the
// points given (the dynamic Gaussians) are processed.
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
  std::vector<double> velocities_;  // V(x_s), laid out as trajectory_
  int kept_steps_ = 0;  // steps whose activations step_workspaces_ keep
  std::vector<FieldWorkspace> step_workspaces_;  // only grows
  std::vector<double> velocity_, gradient_, step_gradient_, d_x_;
  FieldWorkspace workspace_;  // the steps past kept_steps_
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_
