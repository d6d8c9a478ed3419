#ifndef EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_TRAINER_H_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/base/communicator.h"
#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/io/scene.h"
#include "core/flow/flow_lifting.h"
#include "core/loop/euler_chain.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"
#include "costs/joint_objective_options.h"
#include "costs/water_energy_loss.h"
#include "costs/water_texture_loss.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "costs/scene_flow_prior.h"
#include "solvers/train/splat_training.h"
#include "solvers/train/stage_trainer_base.h"
#include "solvers/train/water_densify.h"

namespace es {

// WaterEnergyOptions with both weights 0 (the term off).
inline WaterEnergyOptions NoWaterEnergy() {
  WaterEnergyOptions o;
  o.motion_weight = 0;
  o.detail_weight = 0;
  return o;
}

// The flags that set Stage 3's learning rates, as a divergence message
// names them (es_train's).
struct JointLearningRateFlags {
  SplatLearningRateFlags splat{"--lr_means",         "--lr_log_scales",
                               "--lr_quats",         "--lr_opacity",
                               "--lr_sh_dc/--lr_sh_rest", "--lr_dynamic"};
  std::string motion_triplane = "--lr_motion_triplane";
  std::string motion_mlp = "--lr_motion_mlp";
  std::string residual_triplane = "--lr_residual_triplane";
  std::string residual_mlp = "--lr_residual_mlp";
};

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
  // the fountain preset, docs/results/targets-by-round.md, "4000 joint
  // iterations and a 10x residual weight").
  double residual_weight = 0.01;
  // Stage 1's rates, except that positions start 10x lower: the splats
  // arrive trained.
  SplatLearningRateOptions splat_lr{/*means_initial=*/1.6e-5};
  double lr_motion_triplane = 5e-4;
  double lr_motion_mlp = 1e-4;
  double lr_residual_triplane = 5e-3;
  double lr_residual_mlp = 1e-3;
  double field_lr_final_factor = 0.1;
  JointLearningRateFlags lr_flags;
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
  // weight > 0: with the same frame pairs, WaterTextureLoss on each of the
  // two frames (costs/water_texture_loss.h): the distribution of the
  // water's texture matched to the input frame's. Off by default.
  WaterTextureOptions water_texture;
  // > 0: the sampled frame is also composed as the loop plays it (every
  // water Gaussian at cycle number 0, Alg. 2), rendered, and
  // WaterTextureLoss of that render against the same input frame enters
  // the loss at this weight (with water_texture's bands and projections).
  // Training fits frame i with each Gaussian at its own cycle number; the
  // loop shows them all at 0, whose texture no other loss sees. One more
  // render and backward pass per iteration.
  double loop_texture_weight = 0;
  // >= 1: that term only every this many iterations, at its weight times
  // this (the same expected gradient; JointObjectiveOptions).
  int loop_texture_interval = 1;
  // > 0: the water losses (energy, texture, the loop's texture) ramp in
  // linearly from 0 over this fraction of the iterations. Stage 3 first
  // fits the frames with the water moving, at the static model's
  // fidelity, and then trades some of it for the input's detail and
  // motion; from the start they cost the water ~2 dB that it does not
  // win back on path-traced spray (docs/results/stage3-start.md).
  double water_loss_warmup = 0;
  // > 0: V's displacement (each Euler step) ramps in linearly from 0 over
  // this fraction of the iterations. At 0 every frame renders Stage 1's
  // model; Alg. 1 otherwise carries the water Stage 1 fitted as a time
  // average downstream from the first step (docs/results/stage3-start.md).
  double motion_warmup = 0;
  // Shapes of fields made from scratch (a given V keeps its own). D's
  // cycle_length is set to cycle_length and its max_cycles to cover every
  // frame of the video.
  MotionFieldOptions motion;
  ResidualFieldOptions residual;
  // The arithmetic of V's and D's MLPs in training (the field parameters
  // stay double). Float runs D 1.5x faster, but over three seeds of the
  // README's run its loops moved less like the input (water motion ratio
  // 0.917-0.949 against double's 0.951-0.973; docs/BENCHMARKS.md, "Fields
  // in float"), so double is the default.
  MlpPrecision motion_precision = MlpPrecision::kDouble;
  MlpPrecision residual_precision = MlpPrecision::kDouble;
  EulerOptions euler;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // This many non-finite steps in a row stop the run (DivergenceGuard), as
  // does any block (splats, fields) growing kRunawayGrowth times its
  // initial scale.
  int max_nonfinite_steps = 10;
  // Frames per iteration (solvers/train/data_parallel.h): above 1, each
  // step's gradient is the mean of that many sampled frames' (each with
  // its partner when a pair term is on; the scene-flow prior once),
  // rendered across the ranks of `comm` (nullptr: this process alone).
  // The CPU trainer only.
  int batch_frames = 1;
  Communicator* comm = nullptr;
};

// One step: the objective's terms (JointObjectiveTerms, unweighted; the
// pair's mean with a pair frame), the sampled frames and what the step did.
struct JointIterationStats : JointObjectiveTerms {
  int frame = -1;
  double loss = 0;  // weighted total
  int pair_frame = -1;  // the neighbour rendered for the pair terms
  int num_dynamic = 0;
  bool skipped = false;  // non-finite loss or gradient: no update
  WaterDensifyResult densified;  // after this step's update
};

// What es_train drives: a Stage 3 trainer on the CPU (JointTrainer) or on
// a CUDA device (cuda::DeviceJointTrainer), which take the same steps and
// exchange the same checkpoints.
class JointStageTrainer : public StageTrainer {
 public:
  // Keeps Stage 2's lifted samples as a decaying prior on V
  // (options.flow_prior); needs V, and options.flow_prior.weight > 0 to
  // have an effect. Not checkpointed: a resumed run passes them again.
  virtual void SetSceneFlowPrior(std::vector<SceneFlowSample> samples) = 0;
  virtual bool has_flow_prior() const = 0;

  // One iteration. A non-finite loss or gradient skips the update (counted
  // in skipped_steps()); throws TrainingDiverged after too many in a row or
  // if the parameters become non-finite.
  virtual JointIterationStats Step() = 0;

  // The current model (on a device trainer a download when it changed).
  virtual const LoopModel& model() const = 0;
  // The model to keep when training ends: model() without the Gaussians
  // that no frame shows (PruneInvisible over the video's frames).
  virtual LoopModel FinalModel(int* pruned = nullptr) const = 0;

  virtual JointCheckpoint Save() const = 0;
  // Continues from a checkpoint of a run with the same frames and options;
  // throws InputError naming `source` if its shapes do not match.
  virtual void Restore(const JointCheckpoint& checkpoint,
                       const std::string& source) = 0;
};

// Makes the trainer es_train drives (MakeJointTrainer, or the device
// twin's maker: cuda::MakeDeviceJointTrainer). `initial` are the static
// model's Gaussians; `motion` a pretrained V (its shape and box are kept)
// or nullopt to start V from scratch.
using JointTrainerFactory = std::function<std::unique_ptr<JointStageTrainer>(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion)>;

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_TRAINER_H_
