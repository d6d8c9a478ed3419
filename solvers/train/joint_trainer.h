#ifndef EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/io/scene.h"
#include "core/loop/euler_chain.h"
#include "core/model/gaussians.h"
#include "core/model/dynamic_set.h"
#include "core/model/loop_model.h"
#include "core/render/rasterizer.h"
#include "costs/joint_render_cost.h"
#include "costs/water_energy_loss.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/sparse_adam.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_prior.h"
#include "solvers/train/frame_sampler.h"
#include "solvers/train/splat_training.h"
#include "solvers/train/water_densify.h"

namespace es {

// WaterEnergyOptions with both weights 0 (the term off).
inline WaterEnergyOptions NoWaterEnergy() {
  WaterEnergyOptions o;
  o.motion_weight = 0;
  o.detail_weight = 0;
  return o;
}

// Stage 3 knobs. Splat learning rates follow 3DGS (position rate times the
// scene extent, decaying log-linearly); field rates decay log-linearly to
// field_lr_final_factor times their start over the run.
struct JointTrainerOptions {
  int iterations = 20000;
  uint64_t seed = 0;
  int cycle_length = 15;       // L
  bool use_motion = true;      // false: --no_motion_field / --static_only
  bool use_residual = true;    // false: --no_residual / --static_only
  bool random_start = true;    // false: every start time 0
  double dynamic_threshold = 0.2;  // sigmoid(dynamic_logit) > this: water
  int refresh_interval = 10;       // re-derive the dynamic set this often
  double ssim_weight = 0.2;
  double mask_weight = 0.5;        // 0, or frames without masks: off
  // Mean squared D outputs. At 0.001, D grew through long runs and fitted
  // the training frames' stochastic detail (held-out water PSNR fell on
  // the fountain preset, docs/RESULTS.md).
  double residual_weight = 0.01;
  // Stage 1's rates, except that positions start 10x lower: the splats
  // arrive trained.
  SplatLearningRateOptions splat_lr{/*means_initial=*/1.6e-5};
  double lr_motion_triplane = 5e-4;
  double lr_motion_mlp = 1e-4;
  double lr_residual_triplane = 5e-3;
  double lr_residual_mlp = 1e-3;
  double field_lr_final_factor = 0.1;
  // > 0: water Gaussians are kept at most this large on screen (std dev in
  // pixels at their distance from the training cameras), so they stay
  // particles instead of growing back into smooth sheets.
  double max_dynamic_pixels = 0;
  // The scene-flow prior on V (SetSceneFlowPrior gives it its samples).
  FlowPriorOptions flow_prior;
  // Splitting / cloning of water Gaussians in the first half of the run.
  WaterDensifyOptions water_densify;
  // Either weight > 0: every iteration also renders the sampled frame's
  // neighbour in the video (the next training frame, else the previous)
  // and the step follows the pair's mean loss plus WaterEnergyLoss across
  // the two (costs/water_energy_loss.h): local frame-to-frame change and
  // texture energy matched to the input's in the water. Twice the
  // rendering per iteration. Off by default here; es_train sets its own.
  WaterEnergyOptions water_energy = NoWaterEnergy();
  // Shapes of fields made from scratch (a given V keeps its own). D's
  // cycle_length is set to cycle_length and its max_cycles to cover every
  // frame of the video.
  MotionFieldOptions motion;
  ResidualFieldOptions residual;
  EulerOptions euler;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // This many non-finite steps in a row stop the run (DivergenceGuard).
  int max_nonfinite_steps = 10;
};

struct JointIterationStats {
  int frame = -1;
  double loss = 0;  // weighted total
  double photometric = 0;
  double mask = 0;
  double residual = 0;
  double flow_prior = 0;  // weighted; included in loss
  int pair_frame = -1;    // the neighbour rendered for the energy term
  WaterEnergyTerms energy;  // unweighted; weighted into loss
  int num_dynamic = 0;
  EulerStats euler;
  bool skipped = false;  // non-finite loss or gradient: no update
  WaterDensifyResult densified;  // after this step's update
};

// D's max_cycles for a video of `frames` frames: every cycle number a
// frame can have gets its own encoding.
int CyclesCovering(int frames, int cycle_length);

// Trains a looping model (Stage 3): one sampled training frame per
// iteration, composed at its frame index (Alg. 1 + D), rendered and scored
// by a JointRenderCost evaluated directly into preallocated gradient
// buffers, then one Adam step per block. The dynamic set follows the
// learned probability every refresh_interval iterations: Gaussians that
// stay keep their start time, new ones draw theirs from the seeded RNG.
class JointTrainer {
 public:
  // `initial` are the static model's Gaussians; `motion` a pretrained V
  // (its shape and box are kept) or nullopt to start V from scratch.
  JointTrainer(const std::vector<Frame>* frames, std::vector<int> train,
               const JointTrainerOptions& options, GaussianSet initial,
               std::optional<MotionField> motion);

  // Keeps Stage 2's lifted samples as a decaying prior on V
  // (options.flow_prior); needs V, and options.flow_prior.weight > 0 to
  // have an effect. Not checkpointed: a resumed run passes them again.
  void SetSceneFlowPrior(std::vector<SceneFlowSample> samples);
  bool has_flow_prior() const { return flow_prior_.has_value(); }

  // One iteration. A non-finite loss or gradient skips the update (counted
  // in skipped_steps()); throws TrainingDiverged after too many in a row or
  // if the parameters become non-finite.
  JointIterationStats Step();

  int64_t iteration() const { return iteration_; }
  const LoopModel& model() const { return model_; }
  // The model to keep when training ends: model() without the Gaussians
  // that no frame shows (PruneInvisible over the video's frames).
  LoopModel FinalModel(int* pruned = nullptr) const;
  int64_t skipped_steps() const { return guard_.skipped(); }
  // False right after a skipped step: the state is not one to checkpoint.
  bool last_step_ok() const { return guard_.in_a_row() == 0; }
  bool uses_masks() const { return use_masks_; }
  RenderOptions render_options() const;

  JointCheckpoint Save() const;
  // Continues from a checkpoint of a run with the same frames and options;
  // throws InputError naming `source` if its shapes do not match.
  void Restore(const JointCheckpoint& checkpoint, const std::string& source);

 private:
  void RefreshDynamicSet();
  bool energy_on() const {
    return options_.water_energy.motion_weight > 0 ||
           options_.water_energy.detail_weight > 0;
  }
  // Step's loss and gradient (into grad_ and field_grad_) with the energy
  // term: the pair's mean loss plus the weighted WaterEnergyLoss.
  double PairLossGradient(const Frame& frame, int partner,
                          JointIterationStats* out);
  // Ranks the water Gaussians by their mean view-space gradient over
  // water_densify.views training frames and densifies the top fraction.
  // Stateless (frames and draws follow from seed and iteration), so a
  // resumed run densifies as the uninterrupted one.
  WaterDensifyResult DensifyWaterNow();
  // The per-Gaussian bounds of max_dynamic_pixels, for the current set.
  void UpdateScaleBounds();
  void ClampDynamicScales();
  std::vector<double> FieldLearningRates() const;
  std::vector<std::vector<double>*> FieldBlocks();
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
  // Whether the field parameters were checked finite as a whole since
  // construction or Restore; later steps check only the values they change.
  bool fields_checked_ = false;
  int64_t field_step_ = 0;
  FrameSampler sampler_;
  std::mt19937_64 rng_;
  Rasterizer rasterizer_;
  std::optional<JointRenderCost> cost_;
  std::optional<SceneFlowPrior> flow_prior_;
  // The energy term: each training frame's neighbour (a frame index; -1:
  // none), a second cost (its own rasterizer) and its gradient buffers.
  std::vector<int> partner_;
  bool energy_masks_ = false;
  std::optional<WaterEnergyLoss> energy_;
  std::optional<JointRenderCost> pair_cost_;
  GaussianSet pair_grad_;
  std::vector<double> energy_grad_a_, energy_grad_b_;
  int64_t iteration_ = 0;
  DivergenceGuard guard_;
};

// Below one 8-bit level of opacity a splat cannot change a pixel (the
// rasterizer skips alpha < 1/255).
constexpr double kInvisibleOpacity = 1.0 / 255.0;

// Removes the Gaussians whose opacity is below kInvisibleOpacity in every
// frame: static ones by their opacity, dynamic ones by their opacity with
// D's offset at each frame i in [0, max(num_frames, 2 L)) (every training
// frame, and every cycle index at cycle number 0, as the animation plays
// it). Dynamic indices are remapped, start times kept. Returns the count
// removed.
int PruneInvisible(int num_frames, LoopModel* model);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_TRAINER_H_
