#ifndef EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_
#define EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/fields/motion_field.h"
#include "core/loop/euler_chain_base.h"
#include "core/loop/euler_schedule.h"

namespace es {

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
class EulerChain : public EulerChainBase<MotionField, FieldWorkspace> {
 public:
  EulerChain(const MotionField* field, const EulerOptions& options)
      : EulerChainBase(field, options) {}

  // x_out (n x 3) = x0 (n x 3) advected steps[k] >= 0 times. Keeps the
  // trajectory for Backward; x0 is copied.
  void Forward(const FieldParams& params, int n, const double* x0,
               const int* steps, double* x_out);
  // Given d_x_out (n x 3) for the last Forward (same params), accumulates
  // V's parameter gradients into grads and dL/dx0 into d_x0 (n x 3,
  // nullable).
  void Backward(const FieldParams& params, const double* d_x_out,
                const FieldGradients& grads, double* d_x0);

 private:
  std::vector<double> trajectory_;  // x_s of the active points, s = 0 ..
  std::vector<double> velocities_;  // V(x_s), laid out as trajectory_
  std::vector<double> velocity_, gradient_, step_gradient_, d_x_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_EULER_CHAIN_H_
