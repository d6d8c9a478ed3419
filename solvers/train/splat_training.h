#ifndef EULERSPLAT_SOLVERS_TRAIN_SPLAT_TRAINING_H_
#define EULERSPLAT_SOLVERS_TRAIN_SPLAT_TRAINING_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"
#include "solvers/train/divergence_guard.h"

namespace es {

// What the Stage-1 and Stage-3 trainers share about the splat blocks: the
// training frames' extent and masks, and the splats' learning-rate
// schedule.

// 3DGS radius of the training cameras: 1.1 x the largest distance of a
// camera centre from their mean (at least a small positive value).
double CameraExtent(const std::vector<Frame>& frames,
                    const std::vector<int>& indices);

// Whether every listed frame has a water mask (the mask term needs all).
bool AllHaveMasks(const std::vector<Frame>& frames,
                  const std::vector<int>& indices);

// Adam learning rates of the splat blocks (3DGS's): the position rate is
// multiplied by the scene extent and decays log-linearly from
// means_initial to means_final over the run; the others are constant.
struct SplatLearningRateOptions {
  double means_initial = 1.6e-4;
  double means_final = 1.6e-6;
  double log_scales = 5e-3;
  double quats = 1e-3;
  double opacity = 0.05;
  double sh_dc = 2.5e-3;
  double sh_rest = 2.5e-3 / 20;
  double dynamic = 0.05;  // used only while the mask term is on
};

GaussianLearningRates ScheduledSplatRates(
    const SplatLearningRateOptions& options, double extent,
    int64_t iteration, int iterations, bool learn_dynamic);

// The flags that set those rates, as a divergence message names them.
// es_static's spelling; es_train's options set its own.
struct SplatLearningRateFlags {
  std::string means = "--lr_position";
  std::string log_scales = "--lr_scale";
  std::string quats = "--lr_rotation";
  std::string opacity = "--lr_opacity";
  std::string sh = "--lr_sh_dc/--lr_sh_rest";
  std::string dynamic = "--lr_dynamic";
};

// The splat blocks (kGaussianArrays order: means, log-scales, quaternions,
// opacity logits, SH, dynamic logits) as DivergenceGuard watches them,
// bounded by `initial`'s values: the means at least by the scene extent,
// the others at least by 1.
std::vector<GuardedBlock> GuardedSplatBlocks(
    const GaussianSet& initial, double extent,
    const SplatLearningRateOptions& rates,
    const SplatLearningRateFlags& flags);
// MaxMagnitude of each of g's arrays, in kGaussianArrays order.
std::vector<double> SplatMagnitudes(const GaussianSet& g);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_SPLAT_TRAINING_H_
