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
#include "costs/joint_render_cost.h"
#include "costs/water_energy_loss.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/sparse_adam.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_prior.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/joint_stage_trainer.h"
#include "solvers/train/joint_training_steps.h"

namespace es {

// Trains a looping model (Stage 3): one sampled training frame per
// iteration, composed at its frame index (Alg. 1 + D), rendered and scored
// by a JointRenderCost evaluated directly into preallocated gradient
// buffers, then one Adam step per block. The dynamic set follows the
// learned probability every refresh_interval iterations: Gaussians that
// stay keep their start time, new ones draw theirs from the seeded RNG.
class JointTrainer : public JointStageTrainer {
 public:
  // `initial` are the static model's Gaussians; `motion` a pretrained V
  // (its shape and box are kept) or nullopt to start V from scratch.
  JointTrainer(const std::vector<Frame>* frames, std::vector<int> train,
               const JointTrainerOptions& options, GaussianSet initial,
               std::optional<MotionField> motion);

  void SetSceneFlowPrior(std::vector<SceneFlowSample> samples) override;
  bool has_flow_prior() const override { return flow_prior_.has_value(); }

  JointIterationStats Step() override;

  int64_t iteration() const override { return iteration_; }
  const LoopModel& model() const override { return model_; }
  LoopModel FinalModel(int* pruned = nullptr) const override;
  int64_t skipped_steps() const override { return guard_.skipped(); }
  bool last_step_ok() const override { return guard_.in_a_row() == 0; }
  bool uses_masks() const override { return use_masks_; }
  RenderOptions render_options() const override;

  JointCheckpoint Save() const override;
  void Restore(const JointCheckpoint& checkpoint,
               const std::string& source) override;

 private:
  void RefreshDynamicSet();
  // Step's loss and gradient (into grad_ and field_grad_) with the pair's
  // terms: the pair's mean loss plus the weighted WaterEnergyLoss and
  // WaterTextureLoss.
  double PairLossGradient(const Frame& frame, int partner,
                          JointIterationStats* out);
  // The texture term of the pair (frames a and b, b after a in the video;
  // their renders): its weighted value, its gradient added to the energy's
  // buffers; 0 when off.
  double TextureLossGradient(const double* render_a, const double* render_b,
                             const Frame& a, const Frame& b,
                             JointIterationStats* out);
  // The loop texture term of `frame` (composed at cycle number 0, as
  // es_animate plays it): its weighted value, its gradient added into
  // grad_ and field_grad_ (+=).
  double LoopTextureGradient(const Frame& frame, JointIterationStats* out);
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

  const std::vector<Frame>* frames_;
  std::vector<int> train_;
  JointTrainerOptions options_;
  bool use_masks_ = false;
  double extent_ = 1;
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
  Rasterizer rasterizer_;
  std::optional<JointRenderCost> cost_;
  std::optional<MotionField> prior_field_;  // V at full displacement
  std::optional<SceneFlowPrior> flow_prior_;
  // The energy term: each training frame's neighbour (a frame index; -1:
  // none), a second cost (its own rasterizer) and its gradient buffers.
  std::vector<int> partner_;
  bool energy_masks_ = false;
  std::optional<WaterEnergyLoss> energy_;
  std::optional<WaterTextureLoss> texture_;  // set when its weight is > 0
  std::optional<JointRenderCost> pair_cost_;
  GaussianSet pair_grad_;
  std::vector<double> energy_grad_a_, energy_grad_b_;
  // loop_texture_weight > 0: the frame as the loop plays it (rendered on
  // rasterizer_ after cost_'s backward pass), its texture loss and its
  // image gradient.
  std::optional<JointRenderCost> loop_cost_;
  std::optional<WaterTextureLoss> loop_texture_;
  std::vector<double> loop_grad_;
  int64_t iteration_ = 0;
  DivergenceGuard guard_;
  // Splats then fields (GuardedJointBlocks), bounded at construction.
  std::vector<GuardedBlock> guarded_;
};

// JointTrainerFactory's CPU maker.
std::unique_ptr<JointStageTrainer> MakeJointTrainer(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_
