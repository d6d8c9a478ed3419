#ifndef EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/optim/adam.h"
#include "solvers/train/densify.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/frame_sampler.h"
#include "solvers/train/splat_training.h"

namespace es {

// Stage 1 knobs; defaults are 3DGS's.
struct StaticTrainerOptions {
  int iterations = 10000;
  uint64_t seed = 0;
  int max_sh_degree = 3;
  int sh_degree_interval = 1000;  // raise the SH degree this often
  SplatLearningRateOptions splat_lr;
  double ssim_weight = 0.2;
  double mask_weight = 0.5;  // BCE on the dynamic channel; 0 turns it off
  bool densify = true;
  DensifyOptions densify_options;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // This many non-finite steps in a row stop the run (DivergenceGuard).
  int max_nonfinite_steps = 10;
};

struct IterationStats {
  int frame = -1;
  double loss = 0;  // weighted total
  double photometric = 0;
  double mask = 0;
  bool skipped = false;  // non-finite loss or gradient: no update
};

// Trains a static Gaussian model on the training frames: one sampled frame
// per iteration, its SplatRenderCost evaluated directly into preallocated
// gradient buffers (not through Problem::Evaluate, whose per-parameter
// overhead dominates at this size), an Adam step, SH-degree growth and
// adaptive density control. The mask term is used when mask_weight > 0 and
// every training frame has a mask.
class StaticTrainer {
 public:
  StaticTrainer(const std::vector<Frame>* frames, std::vector<int> train,
                const StaticTrainerOptions& options, GaussianSet initial);

  // One iteration. A non-finite loss or gradient skips the update (counted
  // in skipped_steps()); throws TrainingDiverged after too many in a row or
  // if the parameters become non-finite.
  IterationStats Step();

  int64_t iteration() const { return iteration_; }
  const GaussianSet& gaussians() const { return g_; }
  int64_t skipped_steps() const { return guard_.skipped(); }
  // False right after a skipped step: the state is not one to checkpoint.
  bool last_step_ok() const { return guard_.in_a_row() == 0; }
  bool uses_masks() const { return use_masks_; }
  double scene_extent() const { return extent_; }
  RenderOptions render_options() const;

  Checkpoint Save() const;
  // Continues from a checkpoint of a run with the same frames and options.
  void Restore(const Checkpoint& checkpoint);

 private:
  const std::vector<Frame>* frames_;
  std::vector<int> train_;
  StaticTrainerOptions options_;
  bool use_masks_ = false;
  double extent_ = 1;
  GaussianSet g_;
  GaussianSet grad_;
  GaussianAdam adam_;
  DensityStats stats_;
  FrameSampler sampler_;
  std::mt19937_64 rng_;
  Rasterizer rasterizer_;  // the cost renders with it; densify reads it
  SplatRenderCost cost_;
  std::vector<int> radii_;            // of the last view, reused
  std::vector<double> mean2d_grads_;  // of the last view, reused
  int64_t iteration_ = 0;
  DivergenceGuard guard_;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_
