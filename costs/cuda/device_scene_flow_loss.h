#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_LOSS_H_

// SceneFlowCost::Loss (costs/scene_flow_cost.h) on a CUDA device over
// lifted samples uploaded once: the scene-flow loss of V on a batch of
// them, l = mean_s 0.5 |P_s (V(x_s) - V'(x_s))|^2 (P_s projecting out the
// sample's unseen direction), the batch chosen by indices
// drawn on the host (only those are uploaded per call). What the device
// scene-flow prior (Stage 3) and the device V pretraining (Stage 2) both
// evaluate. No CUDA types; failures throw CudaError.

#include <vector>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/flow/flow_lifting.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DeviceSceneFlowLoss {
 public:
  // `field` must outlive this; `samples` non-empty.
  DeviceSceneFlowLoss(const DeviceMotionField* field,
                      const std::vector<SceneFlowSample>& samples);

  // scale * l at `params` (device blocks) over the samples `indices`
  // (non-empty), with scale * dl/dtheta added (+=) to `grads` (device
  // blocks, each nullable; triplane_chunks must be null). Only the loss's
  // sum comes back.
  double AddLossAndGradient(const FieldParams& params,
                            const std::vector<int>& indices, double scale,
                            const FieldGradients& grads);

  int num_samples() const { return num_samples_; }

 private:
  const DeviceMotionField* field_;
  int num_samples_;
  // num_samples x 3 each
  DeviceBuffer<double> samples_x_, samples_v_, samples_unseen_;
  DeviceBuffer<int> batch_indices_;
  // The batch's positions, targets, unseen directions, V (then P (V - V'))
  // and d l / d V.
  DeviceBuffer<double> x_, target_, unseen_, velocity_, d_velocity_;
  DeviceBuffer<double> partials_, sum_;
  DeviceFieldWorkspace workspace_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_LOSS_H_
