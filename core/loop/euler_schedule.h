#ifndef EULERSPLAT_CORE_LOOP_EULER_SCHEDULE_H_
#define EULERSPLAT_CORE_LOOP_EULER_SCHEDULE_H_

#include <cstddef>
#include <cstdint>
#include <vector>

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

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_EULER_SCHEDULE_H_
