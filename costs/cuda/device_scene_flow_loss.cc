#include "costs/cuda/device_scene_flow_loss.h"

#include <glog/logging.h>

#include "costs/cuda/mean_loss_kernels.h"
#include "costs/cuda/scene_flow_loss_kernels.h"

namespace es {
namespace cuda {

DeviceSceneFlowLoss::DeviceSceneFlowLoss(
    const DeviceMotionField* field,
    const std::vector<SceneFlowSample>& samples)
    : field_(field), num_samples_(static_cast<int>(samples.size())) {
  CHECK(field != nullptr);
  CHECK(!samples.empty());
  std::vector<double> x, v, unseen;
  x.reserve(3 * samples.size());
  v.reserve(3 * samples.size());
  unseen.reserve(3 * samples.size());
  for (const SceneFlowSample& s : samples) {
    x.insert(x.end(), s.x.data(), s.x.data() + 3);
    v.insert(v.end(), s.v.data(), s.v.data() + 3);
    unseen.insert(unseen.end(), s.unseen.data(), s.unseen.data() + 3);
  }
  samples_x_.Upload(x);
  samples_v_.Upload(v);
  samples_unseen_.Upload(unseen);
}

double DeviceSceneFlowLoss::AddLossAndGradient(
    const FieldParams& params, const std::vector<int>& indices, double scale,
    const FieldGradients& grads) {
  CHECK(!indices.empty());
  const int n = static_cast<int>(indices.size());
  const long long values = 3LL * n;
  batch_indices_.Upload(indices);
  x_.Resize(values);
  target_.Resize(values);
  unseen_.Resize(values);
  velocity_.Resize(values);
  GatherSceneFlowBatch(n, batch_indices_.data(), samples_x_.data(),
                       samples_v_.data(), samples_unseen_.data(), x_.data(),
                       target_.data(), unseen_.data());
  field_->Evaluate(params, n, x_.data(), velocity_.data(), &workspace_);
  ConstrainedDifference(n, target_.data(), unseen_.data(), velocity_.data());
  // SceneFlowCost::Loss's l = 0.5 sum |P r|^2 / n with d l / d V = P P r /
  // n, scaled here rather than after the backward.
  const bool gradient = grads.triplane != nullptr || grads.mlp != nullptr;
  if (gradient) d_velocity_.Resize(values);
  const int blocks = MeanLossBlocks(values);
  partials_.Resize(blocks);
  sum_.Resize(1);
  ResidualL2Terms(values, velocity_.data(), scale / n,
                  gradient ? d_velocity_.data() : nullptr, partials_.data());
  SumMeanLossPartials(blocks, partials_.data(), sum_.data());
  if (gradient) {
    ProjectOutUnseen(n, unseen_.data(), d_velocity_.data());
    field_->Backward(params, d_velocity_.data(), grads, nullptr, &workspace_);
  }
  double sum;
  sum_.Download(&sum);
  return scale * (0.5 * sum / n);
}

}  // namespace cuda
}  // namespace es
