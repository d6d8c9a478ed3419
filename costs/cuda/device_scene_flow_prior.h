#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_PRIOR_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_PRIOR_H_

// SceneFlowPrior (costs/scene_flow_prior.h) on a CUDA device: Stage 2's
// scene-flow loss of V kept during joint training,
//   l = w(it) mean_s 0.5 |V(x_s) - V'(x_s)|^2 / mean_all |V'|^2,
// over the same mini-batch as the CPU's for the same (seed, iteration)
// (DrawFlowPriorBatch draws it on the host; DeviceSceneFlowLoss evaluates
// it). No CUDA types; failures throw CudaError.

#include <cstdint>
#include <vector>

#include "core/fields/cuda/device_motion_field.h"
#include "costs/cuda/device_scene_flow_loss.h"
#include "costs/scene_flow_prior.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DeviceSceneFlowPrior {
 public:
  // `field` must outlive this; `samples` non-empty, uploaded once.
  DeviceSceneFlowPrior(const DeviceMotionField* field,
                       std::vector<SceneFlowSample> samples,
                       const FlowPriorOptions& options);

  // w(it) for a run of `iterations`.
  double Weight(int64_t iteration, int64_t iterations) const;

  // l at `params` (device blocks) over iteration `iteration`'s batch, with
  // dl/dtheta added (+=) to `grads` (device blocks, each nullable;
  // triplane_chunks must be null). Only the loss's sum comes back.
  double AddLossAndGradient(const FieldParams& params, int64_t iteration,
                            int64_t iterations, uint64_t seed,
                            const FieldGradients& grads);

  int num_samples() const { return loss_.num_samples(); }

 private:
  FlowPriorOptions options_;
  double inverse_mean_square_speed_;
  std::vector<int> indices_;  // the batch, drawn on the host
  DeviceSceneFlowLoss loss_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_SCENE_FLOW_PRIOR_H_
