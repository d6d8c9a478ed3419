#ifndef EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

#include "core/base/communicator.h"
#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/optim/adam.h"
#include "solvers/train/data_parallel.h"
#include "solvers/train/densify.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/splat_training.h"
#include "solvers/train/stage_trainer_base.h"
#include "solvers/train/static_stage_trainer.h"

namespace es {

// Stage 1 knobs; defaults are 3DGS's.
struct StaticTrainerOptions {
  int iterations = 10000;
  uint64_t seed = 0;
  int max_sh_degree = 3;
  int sh_degree_interval = 1000;  // raise the SH degree this often
  SplatLearningRateOptions splat_lr;
  // What sets those rates, for a divergence message (es_static's flags).
  SplatLearningRateFlags lr_flags;
  double ssim_weight = 0.2;
  double mask_weight = 0.5;  // BCE on the dynamic channel; 0 turns it off
  bool densify = true;
  DensifyOptions densify_options;
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // This many non-finite steps in a row stop the run (DivergenceGuard), as
  // does any splat block growing kRunawayGrowth times its initial scale.
  int max_nonfinite_steps = 10;
  // Frames per iteration (solvers/train/data_parallel.h): above 1, each
  // step's gradient is the mean over that many sampled frames, rendered
  // across the ranks of `comm` (nullptr: this process alone). 1 is the
  // one-frame step of 3DGS.
  int batch_frames = 1;
  Communicator* comm = nullptr;
};

// Stage 1's loss terms, render options and schedule, shared by StaticTrainer
// and its device twin (solvers/train/cuda/device_static_trainer.h).
// `iteration` is the number of steps taken before the step in question.

// 3DGS caps opacities at this on every reset.
constexpr double kStaticResetOpacity = 0.01;

ImageLossTerms StaticLossTerms(const StaticTrainerOptions& options,
                               bool use_masks);
RenderOptions StaticRenderOptions(const StaticTrainerOptions& options);
// Whether the SH degree rises (by one) before this step.
bool ShDegreeRises(const StaticTrainerOptions& options, int64_t iteration,
                   int sh_degree);
// Whether this step gathers densification statistics (and may densify or
// reset opacities after its update).
bool Densifying(const StaticTrainerOptions& options, int64_t iteration);
// After a densifying step, with `done` steps taken: whether to clone,
// split and prune now, and whether to reset opacities now.
bool DensifyDue(const StaticTrainerOptions& options, int64_t done);
bool OpacityResetDue(const StaticTrainerOptions& options, int64_t done);

// Trains a static Gaussian model on the training frames: one sampled frame
// per iteration, its SplatRenderCost evaluated directly into preallocated
// gradient buffers (not through Problem::Evaluate, whose per-parameter
// overhead dominates at this size), an Adam step, SH-degree growth and
// adaptive density control. The mask term is used when mask_weight > 0 and
// every training frame has a mask.
class StaticTrainer
    : public StageTrainerBase<StaticStageTrainer, StaticTrainerOptions> {
 public:
  StaticTrainer(const std::vector<Frame>* frames, std::vector<int> train,
                const StaticTrainerOptions& options, GaussianSet initial);

  IterationStats Step() override;

  const GaussianSet& gaussians() const override { return g_; }
  double scene_extent() const override { return extent_; }
  RenderOptions render_options() const override;

  Checkpoint Save() const override;
  void Restore(const Checkpoint& checkpoint) override;

  // The gradient of the last step that was not skipped (with batches: the
  // batch's mean over every rank).
  const GaussianSet& last_gradient() const { return grad_; }
  size_t allreduce_bytes() const override {
    return batch_sum_.bytes_per_reduction();
  }

 private:
  // Step's gradient with batch_frames > 1: the batch's mean over the ranks,
  // into grad_; the views' densification statistics (when `densifying`)
  // into stats_. Returns the batch's mean loss terms in `out`.
  void BatchGradient(bool densifying, IterationStats* out);

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
  Communicator* comm_;
  PackedSum batch_sum_;       // a batch's gradients, stats and loss terms
  DensityStats batch_stats_;  // a batch's views
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_STATIC_TRAINER_H_
