#ifndef EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_H_
#define EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_H_

#include <functional>
#include <memory>
#include <string>

#include "core/io/scene.h"
#include "solvers/eval/static_eval.h"
#include "solvers/train/static_stage_trainer.h"
#include "solvers/train/static_trainer.h"

namespace es {

struct StaticStageOptions {
  std::string scene_dir;
  std::string out_dir;
  SceneOptions scene;
  StaticTrainerOptions trainer;
  bool resume = false;             // continue from out_dir/checkpoint.bin
  int checkpoint_every = 1000;     // iterations; 0: never
  int log_every = 100;             // iterations; 0: silent
  // Held-out PSNR into out_dir/history.csv every this many iterations (and
  // always at the end); 0: only at the end.
  int eval_every = 1000;
  double dynamic_threshold = 0.2;  // sigmoid(dynamic_logit) above: water
  bool profile = false;  // print the per-stage time of the iterations
};

struct StaticStageResult {
  StaticMetrics test;
  int num_gaussians = 0;
  int num_dynamic = 0;
  double seconds = 0;  // training time of this run (excludes loading)
  double iterations_per_second = 0;
};

// The pieces of Stage 1 shared by es_static and bench_static.

// Loads a scene Stage 1 can train on; throws InputError if it has no
// training frames or no points to seed from.
Scene LoadStaticScene(const std::string& scene_dir,
                      const SceneOptions& options);

// The Gaussians Stage 1 starts from: the scene's points, 3-NN scales.
GaussianSet InitialStaticGaussians(const Scene& scene);

// A trainer on the scene's training split, seeded from its points (3-NN
// scales). `scene` must outlive it.
std::unique_ptr<StaticTrainer> MakeStaticTrainer(
    const Scene& scene, const StaticTrainerOptions& options);

// Makes the trainer RunStaticStage drives (MakeStaticTrainer, or a device
// twin's maker: cuda::MakeDeviceStaticTrainer).
using StaticTrainerFactory = std::function<std::unique_ptr<StaticStageTrainer>(
    const Scene& scene, const StaticTrainerOptions& options)>;

// The model as Stage 1 writes and evaluates it: without masks, every
// dynamic logit is set well below any threshold (no Gaussian is water).
GaussianSet StaticModel(const StaticStageTrainer& trainer);

// Held-out metrics of StaticModel(trainer) on the scene's test split.
StaticMetrics EvaluateHeldOut(const StaticStageTrainer& trainer,
                              const Scene& scene);

// Stage 1: loads the scene, seeds Gaussians from its points (3-NN scales),
// trains on the training split (resuming if asked), evaluates on the
// held-out frames and writes out_dir/static.ply, out_dir/metrics.json and
// out_dir/history.csv (a row every log_every iterations: losses, Gaussians,
// held-out PSNR at eval steps). out_dir is checked for writing first.
// Without masks there is no mask term and no Gaussian is marked dynamic:
// every dynamic logit is written well below the threshold. Throws
// InputError for bad options or inputs. `make_trainer` picks the device.
StaticStageResult RunStaticStage(
    const StaticStageOptions& options,
    const StaticTrainerFactory& make_trainer = MakeStaticTrainer);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_STATIC_STAGE_H_
