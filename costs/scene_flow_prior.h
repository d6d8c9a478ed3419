#ifndef EULERSPLAT_COSTS_SCENE_FLOW_PRIOR_H_
#define EULERSPLAT_COSTS_SCENE_FLOW_PRIOR_H_

#include <cstdint>
#include <vector>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "costs/scene_flow_cost.h"

namespace es {

struct FlowPriorOptions {
  // Weight at the first joint iteration; 0 turns the prior off.
  double weight = 0;
  // The weight decays log-linearly to weight * final_factor at the last
  // iteration: the lifted flow steers V early, the images decide late.
  double final_factor = 0.1;
  int batch_size = 1024;  // samples per iteration
};

// Iteration `iteration`'s mini-batch of a run seeded `seed`: each of
// indices->size() entries drawn uniformly from [0, num_samples). A function
// of (seed, iteration) alone, shared by SceneFlowPrior and its device twin
// (costs/cuda/device_scene_flow_prior.h) so both train on the same batches.
void DrawFlowPriorBatch(uint64_t seed, int64_t iteration, int num_samples,
                        std::vector<int>* indices);

// w(it) of a run of `iterations`: options.weight decaying log-linearly to
// options.weight * options.final_factor.
double FlowPriorWeight(const FlowPriorOptions& options, int64_t iteration,
                       int64_t iterations);

// 1 / mean_s |V'(x_s)|^2 over `samples` (1 when every target is 0): the
// prior's normalization.
double InverseMeanSquareSpeed(const std::vector<SceneFlowSample>& samples);

// Replaces each sample's target by `field`'s V at the sample, whole (its
// unseen direction cleared): a prior on those samples then holds V to that
// field, Stage 2's smooth fit, instead of to the lifted flow's noise.
void TargetFieldAtSamples(const MotionField& field,
                          std::vector<SceneFlowSample>* samples);

// Stage 2's scene-flow loss kept during joint training (V otherwise drifts
// from the flow initialization, since the photometric loss of stochastic
// water does not pin V to the true velocity):
//   l = w(it) * mean_s 0.5 |V(x_s) - V'(x_s)|^2 / mean_all |V'|^2
// over a random mini-batch of the lifted samples. Dividing by the mean
// squared target speed makes w independent of the scene's units.
class SceneFlowPrior {
 public:
  // `field` must outlive this; `samples` non-empty.
  SceneFlowPrior(const MotionField* field,
                 std::vector<SceneFlowSample> samples,
                 const FlowPriorOptions& options);

  // w(it) for a run of `iterations`.
  double Weight(int64_t iteration, int64_t iterations) const;

  // l at `params` over iteration `iteration`'s batch, with dl/dtheta added
  // (+=) to `grads`. The batch is a function of (seed, iteration) alone, so
  // a resumed run draws the same batches without saved state.
  double AddLossAndGradient(const FieldParams& params, int64_t iteration,
                            int64_t iterations, uint64_t seed,
                            const FieldGradients& grads);

  int num_samples() const { return static_cast<int>(samples_.size()); }

 private:
  const MotionField* field_;
  std::vector<SceneFlowSample> samples_;
  FlowPriorOptions options_;
  double inverse_mean_square_speed_ = 1;
  SceneFlowBatch batch_;
  SceneFlowCost cost_;
  std::vector<int> indices_;
  std::vector<double> grad_triplane_, grad_mlp_;
  std::vector<char> chunks_;  // grad_triplane_'s written chunks
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_SCENE_FLOW_PRIOR_H_
