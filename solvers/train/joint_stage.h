#ifndef EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_H_
#define EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_H_

#include <cmath>
#include <cstdint>
#include <string>

#include "core/io/scene.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/train/joint_stage_trainer.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/water_particles.h"

namespace es {

struct JointStageOptions {
  std::string scene_dir;
  // static.ply (Stage 1) and, optionally, motion_field.bin and
  // scene_flow_samples.bin (Stage 2).
  std::string init_dir;
  std::string out_dir;
  SceneOptions scene;
  JointTrainerOptions trainer;
  bool resume = false;          // continue from out_dir/joint_checkpoint.bin
  int checkpoint_interval = 1000;  // iterations; 0: never
  int log_interval = 100;          // progress line + history row; 0: neither
  // Held-out PSNR into out_dir/history.csv at iteration 0 (Stage 1's model
  // printed beside it), every this many iterations and always at the end;
  // 0: only at the end.
  int eval_interval = 1000;
  bool flow_init = true;  // false: V from scratch even if Stage 2 wrote one
  // Hold V to Stage 2's own V at the samples' points instead of to the
  // lifted samples (the scene-flow prior's targets).
  bool flow_prior_to_field = false;
  // particles.particle_pixels > 0: split the static model's large water
  // Gaussians into particles before training (its dynamic_threshold and
  // seed are the trainer's); 0: keep the water as Stage 1 left it.
  WaterParticleOptions particles{/*particle_pixels=*/0};
  // Std of the input frames' per-pixel noise, which the water losses do
  // not ask the render to paint (costs/water_input_noise.h): < 0:
  // estimated from the training frames; >= 0: this on every channel.
  double input_noise = -1;
  bool profile = false;  // print the per-stage time of the iterations
  // Set: "training on <device_name>" is printed once the trainer is made.
  std::string device_name;
};

struct JointStageResult {
  LoopMetrics test;  // the final model's, on the held-out frames
  int64_t iterations = 0;  // the trainer's count at the end
  double seconds = 0;  // this run's training time (loading, evaluation not)
  int num_gaussians = 0, num_dynamic = 0;  // of the final (pruned) model
  bool flow_init = false;  // V started from Stage 2's
  double final_loss = NAN;  // mean loss of the last logged interval (or NaN)
  // Stage 1's model on the held-out frames as the start of Stage 3 is
  // measured (NaN without evaluation: eval_interval 0).
  LoopMetrics stage1{0, NAN, NAN, NAN, NAN};
};

// Stage 3: loads the scene and init_dir's static model (and Stage 2's V and
// scene-flow samples where there are some and they are wanted), splits the
// water into particles if asked, trains V, D and the splats (resuming from
// out_dir/joint_checkpoint.bin if asked and present; checkpoints every
// checkpoint_interval), prunes the Gaussians no frame shows, evaluates on
// the held-out frames and writes the model (loop.txt, canonical.ply,
// fields), out_dir/history.csv and, last, out_dir/metrics.json: the
// driver takes loop.txt and metrics.json together as the stage being done,
// so a failure before the end leaves no metrics.json. out_dir is checked
// for writing first. Throws InputError for bad inputs (naming them) and for
// a cycle longer than the video. `make_trainer` picks the device.
JointStageResult RunJointStage(
    const JointStageOptions& options,
    const JointTrainerFactory& make_trainer = MakeJointTrainer);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_JOINT_STAGE_H_
