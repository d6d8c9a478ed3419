#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_EULER_CHAIN_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_EULER_CHAIN_H_

// Alg. 1, the Euler chain (EulerChain, core/loop/euler_chain.h), on the
// device: positions, trajectory, velocities and V's activations stay in
// device memory; the same lockstep batches (points sorted by step count,
// the active ones a prefix), the same stress rule (TakeSafeStep) and
// counts, the same memory budget for kept activations (later steps are
// evaluated again in Backward). No CUDA types; failures throw CudaError.

#include <vector>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/loop/euler_chain.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Keeps its state between Forward and Backward: not thread-safe.
class DeviceEulerChain
    : public EulerChainBase<DeviceMotionField, DeviceFieldWorkspace> {
 public:
  DeviceEulerChain(const DeviceMotionField* field,
                   const EulerOptions& options)
      : EulerChainBase(field, options) {}

  // x_out (device, n x 3) = x0 (device, n x 3) advected steps[k] >= 0
  // times (steps: a host array of n). Keeps the trajectory for Backward;
  // x0 is copied.
  void Forward(const FieldParams& params, int n, const double* x0,
               const int* steps, double* x_out);
  // Given d_x_out (device, n x 3) for the last Forward (same params),
  // accumulates V's parameter gradients into grads (device) and dL/dx0
  // into d_x0 (device, n x 3, nullable).
  void Backward(const FieldParams& params, const double* d_x_out,
                const FieldGradients& grads, double* d_x0);

 private:
  DeviceBuffer<int> order_;  // schedule_.order on the device
  DeviceBuffer<double> trajectory_;  // x_s of the active points, s = 0 ..
  DeviceBuffer<double> velocities_;  // V(x_s), laid out as trajectory_
  DeviceBuffer<unsigned long long> counters_;  // clamped, non-finite
  DeviceBuffer<double> velocity_, gradient_, step_gradient_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_EULER_CHAIN_H_
