#ifndef EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"
#include "costs/joint_objective.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/sparse_adam.h"
#include "solvers/train/data_parallel.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/joint_stage_trainer.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/stage_trainer_base.h"

namespace es {

// Trains a looping model (Stage 3): one sampled training frame (and its
// neighbour, for the pair terms) per iteration, scored by the
// JointObjective (costs/joint_objective.h, the scene-flow prior on V
// included) into preallocated gradient buffers, then one Adam step per
// block.
// The dynamic set follows the learned probability every refresh_interval
// iterations: Gaussians that stay keep their start time, new ones draw
// theirs from the seeded RNG.
class JointTrainer
    : public StageTrainerBase<JointStageTrainer, JointTrainerOptions> {
 public:
  // `initial` are the static model's Gaussians; `motion` a pretrained V
  // (its shape and box are kept) or nullopt to start V from scratch.
  JointTrainer(const std::vector<Frame>* frames, std::vector<int> train,
               const JointTrainerOptions& options, GaussianSet initial,
               std::optional<MotionField> motion);

  void SetSceneFlowPrior(std::vector<SceneFlowSample> samples) override;
  bool has_flow_prior() const override {
    return objective_->has_scene_flow_prior();
  }

  JointIterationStats Step() override;

  const LoopModel& model() const override { return model_; }
  LoopModel FinalModel(int* pruned = nullptr) const override;
  RenderOptions render_options() const override;

  JointCheckpoint Save() const override;
  void Restore(const JointCheckpoint& checkpoint,
               const std::string& source) override;

  // With batch_frames > 1: the last batch's mean gradient over the ranks
  // (JointBlockLayout's blocks one after the other, without the scene-flow
  // prior), then its mean loss terms.
  const std::vector<double>& last_batch_gradient() const {
    return batch_sum_.data();
  }
  size_t allreduce_bytes() const override {
    return batch_sum_.bytes_per_reduction();
  }

 private:
  // Step's gradient with batch_frames > 1: the batch's mean over the ranks
  // plus the prior, into `gradients` (the splats' rows overwritten, the
  // fields' zero before); returns the loss, the terms into `out`.
  double BatchGradient(double const* const* params, double** gradients,
                       JointIterationStats* out);
  void RefreshDynamicSet();
  // Ranks the water Gaussians by their mean view-space gradient over
  // water_densify.views training frames and densifies the top fraction.
  // Stateless (frames and draws follow from seed and iteration), so a
  // resumed run densifies as the uninterrupted one.
  WaterDensifyResult DensifyWaterNow();
  // The per-Gaussian bounds of max_dynamic_pixels, for the current set.
  void UpdateScaleBounds();
  void ClampDynamicScales();
  // Per cost block, the chunk flags (SparseAdam::chunk_flags) of the
  // fields' triplane blocks, nullptr for the others.
  std::vector<char*> TriplaneChunkFlags();
  // Per cost block, its gradient: grad_ (sized to the model first) and the
  // fields' gradients.
  std::vector<double*> GradientBlocks();

  LoopModel model_;
  std::vector<double> dynamic_max_scale_;  // per dynamic Gaussian
  int initial_dynamic_ = 0;  // water Gaussians at construction
  GaussianSet grad_;
  GaussianAdam adam_;
  // Per field block (V's triplane and MLP, then D's): the gradient buffer,
  // all zero between steps (SparseAdam hands it back cleared), and Adam.
  std::vector<std::vector<double>> field_grad_;
  std::vector<SparseAdam> field_adam_;
  int64_t field_step_ = 0;
  FrameSampler sampler_;
  std::mt19937_64 rng_;
  // The loss and gradient of a step (the sampled frame, its partner).
  std::optional<JointObjective> objective_;
  // Each training frame's neighbour for the pair terms (a frame index;
  // -1: none).
  std::vector<int> partner_;
  Communicator* comm_;
  PackedSum batch_sum_;  // a batch's gradients and loss terms
  // One frame's field gradients in a batch (zero between frames): a pair's
  // halving must not reach the other frames' sum.
  std::vector<std::vector<double>> frame_field_grad_;
};

// JointTrainerFactory's CPU maker.
std::unique_ptr<JointStageTrainer> MakeJointTrainer(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_
