#include "costs/scene_flow_prior.h"

#include <algorithm>
#include <random>

#include <glog/logging.h>

#include "core/fields/gradient_chunks.h"
#include "core/base/lr_schedule.h"

namespace es {

void DrawFlowPriorBatch(uint64_t seed, int64_t iteration, int num_samples,
                        std::vector<int>* indices) {
  CHECK_GT(num_samples, 0);
  std::seed_seq seq{static_cast<uint32_t>(seed),
                    static_cast<uint32_t>(seed >> 32),
                    static_cast<uint32_t>(iteration),
                    static_cast<uint32_t>(iteration >> 32)};
  std::mt19937 rng(seq);
  std::uniform_int_distribution<int> pick(0, num_samples - 1);
  for (int& i : *indices) i = pick(rng);
}

double FlowPriorWeight(const FlowPriorOptions& options, int64_t iteration,
                       int64_t iterations) {
  return LogLinearLr(options.weight, options.weight * options.final_factor,
                     iteration, iterations);
}

double InverseMeanSquareSpeed(const std::vector<SceneFlowSample>& samples) {
  double sum = 0;
  for (const SceneFlowSample& s : samples) sum += s.v.squaredNorm();
  const double mean = sum / samples.size();
  return mean > 0 ? 1.0 / mean : 1.0;
}

void TargetFieldAtSamples(const MotionField& field,
                          std::vector<SceneFlowSample>* samples) {
  SceneFlowBatch all;
  all.AssignAll(*samples);
  std::vector<double> v(all.x.size());
  FieldWorkspace ws;
  field.Evaluate(field.params(), all.size(), all.x.data(), v.data(), &ws);
  for (int i = 0; i < all.size(); ++i) {
    (*samples)[i].v = Eigen::Map<const Eigen::Vector3d>(&v[3 * i]);
    (*samples)[i].unseen.setZero();
  }
}

SceneFlowPrior::SceneFlowPrior(const MotionField* field,
                               std::vector<SceneFlowSample> samples,
                               const FlowPriorOptions& options)
    : field_(field),
      samples_(std::move(samples)),
      options_(options),
      cost_(field, &batch_) {
  CHECK(field != nullptr);
  CHECK(!samples_.empty());
  CHECK_GT(options_.batch_size, 0);
  inverse_mean_square_speed_ = InverseMeanSquareSpeed(samples_);
  indices_.resize(std::min<size_t>(options_.batch_size, samples_.size()));
  grad_triplane_.resize(field->triplane().num_params());
  chunks_.resize(NumGradientChunks(grad_triplane_.size()));
  grad_mlp_.resize(field->mlp().num_params());
}

double SceneFlowPrior::Weight(int64_t iteration, int64_t iterations) const {
  return FlowPriorWeight(options_, iteration, iterations);
}

double SceneFlowPrior::AddLossAndGradient(const FieldParams& params,
                                          int64_t iteration,
                                          int64_t iterations, uint64_t seed,
                                          const FieldGradients& grads) {
  const double scale =
      Weight(iteration, iterations) * inverse_mean_square_speed_;
  if (scale <= 0) return 0;
  DrawFlowPriorBatch(seed, iteration, num_samples(), &indices_);
  batch_.Assign(samples_, indices_);
  // grad_triplane_ is all zero between calls: only the chunks the batch
  // writes are added and cleared.
  std::fill(grad_mlp_.begin(), grad_mlp_.end(), 0.0);
  const double loss = cost_.Loss(
      params, {grad_triplane_.data(), grad_mlp_.data(), chunks_.data()});
  const size_t size = grad_triplane_.size();
  for (size_t c = 0; c < chunks_.size(); ++c) {
    if (!chunks_[c]) continue;
    chunks_[c] = 0;
    const size_t begin = c * kGradientChunk;
    const size_t end = std::min(size, begin + kGradientChunk);
    for (size_t k = begin; k < end; ++k) {
      if (grads.triplane != nullptr)
        grads.triplane[k] += scale * grad_triplane_[k];
      grad_triplane_[k] = 0.0;
    }
    if (grads.triplane != nullptr && grads.triplane_chunks != nullptr)
      grads.triplane_chunks[c] = 1;
  }
  if (grads.mlp != nullptr) {
    for (size_t k = 0; k < grad_mlp_.size(); ++k)
      grads.mlp[k] += scale * grad_mlp_[k];
  }
  return scale * loss;
}

}  // namespace es
