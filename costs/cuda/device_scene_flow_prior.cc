#include "costs/cuda/device_scene_flow_prior.h"

#include <algorithm>

#include <glog/logging.h>

namespace es {
namespace cuda {

DeviceSceneFlowPrior::DeviceSceneFlowPrior(
    const DeviceMotionField* field, std::vector<SceneFlowSample> samples,
    const FlowPriorOptions& options)
    : options_(options),
      inverse_mean_square_speed_(InverseMeanSquareSpeed(samples)),
      indices_(std::min<size_t>(options.batch_size, samples.size())),
      loss_(field, samples) {
  CHECK_GT(options_.batch_size, 0);
}

double DeviceSceneFlowPrior::Weight(int64_t iteration,
                                    int64_t iterations) const {
  return FlowPriorWeight(options_, iteration, iterations);
}

double DeviceSceneFlowPrior::AddLossAndGradient(const FieldParams& params,
                                                int64_t iteration,
                                                int64_t iterations,
                                                uint64_t seed,
                                                const FieldGradients& grads) {
  const double scale =
      Weight(iteration, iterations) * inverse_mean_square_speed_;
  if (scale <= 0) return 0;
  DrawFlowPriorBatch(seed, iteration, num_samples(), &indices_);
  return loss_.AddLossAndGradient(params, indices_, scale, grads);
}

}  // namespace cuda
}  // namespace es
