#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_ANIMATOR_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_ANIMATOR_H_

// Alg. 2 (LoopAnimator, core/loop/loop_animator.h) on the device: Start
// places every Gaussian at its cycle index with DeviceEulerChain, Advance
// takes one Euler step per Gaussian per frame with one batch of V over all
// of them, resetting a Gaussian to its canonical position when its cycle
// index wraps from L - 1 to 0. Positions and cycle indices stay in device
// memory. No CUDA types; failures throw CudaError.

#include <vector>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/loop/cuda/device_euler_chain.h"
#include "core/loop/euler_chain.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceLoopAnimator {
 public:
  DeviceLoopAnimator(const DeviceMotionField* field,
                     const EulerOptions& options, int cycle_length);

  // x0 (device, n x 3) is copied; start_times (host) has n entries in
  // [0, L).
  void Start(const FieldParams& params, int n, const double* x0,
             const std::vector<int>& start_times, int frame);
  void Advance(const FieldParams& params);

  int frame() const { return frame_; }
  int size() const { return n_; }
  // Device arrays in the order of x0: n x 3 positions, n cycle indices.
  const double* positions() const { return positions_.data(); }
  const int* cycle_indices() const { return cycle_index_.data(); }
  // Accumulated since Start (reads the device's counts).
  EulerStats stats() const;

 private:
  const DeviceMotionField* field_;
  int cycle_length_;
  int frame_ = 0, n_ = 0;
  DeviceEulerChain chain_;
  EulerStats start_stats_;  // the chain's, at Start
  int64_t advanced_ = 0;    // velocity evaluations since Start
  DeviceBuffer<double> canonical_, positions_, velocity_;
  DeviceBuffer<int> cycle_index_;
  DeviceBuffer<unsigned long long> counters_;  // clamped, non-finite
  DeviceFieldWorkspace workspace_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_ANIMATOR_H_
