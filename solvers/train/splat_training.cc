#include "solvers/train/splat_training.h"

#include <glog/logging.h>

#include <algorithm>

#include "core/base/lr_schedule.h"

namespace es {

double CameraExtent(const std::vector<Frame>& frames,
                    const std::vector<int>& indices) {
  CHECK(!indices.empty());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : indices) mean += frames[i].camera.Center();
  mean /= indices.size();
  double radius = 0;
  for (int i : indices)
    radius = std::max(radius, (frames[i].camera.Center() - mean).norm());
  return std::max(1.1 * radius, 1e-6);
}

bool AllHaveMasks(const std::vector<Frame>& frames,
                  const std::vector<int>& indices) {
  for (int i : indices)
    if (frames[i].mask.empty()) return false;
  return true;
}

GaussianLearningRates ScheduledSplatRates(
    const SplatLearningRateOptions& o, double extent, int64_t iteration,
    int iterations, bool learn_dynamic) {
  GaussianLearningRates lr;
  lr.means = extent * LogLinearLr(o.means_initial, o.means_final, iteration,
                                  iterations);
  lr.log_scales = o.log_scales;
  lr.quats = o.quats;
  lr.opacity_logits = o.opacity;
  lr.sh_dc = o.sh_dc;
  lr.sh_rest = o.sh_rest;
  lr.dynamic_logits = learn_dynamic ? o.dynamic : 0.0;
  return lr;
}

std::vector<GuardedBlock> GuardedSplatBlocks(
    const GaussianSet& initial, double extent,
    const SplatLearningRateOptions& rates,
    const SplatLearningRateFlags& flags) {
  return {
      {"the Gaussians' means", "the position learning rate", flags.means,
       rates.means_initial, RunawayBound(initial.means, extent)},
      {"the Gaussians' log-scales", "the log-scale learning rate",
       flags.log_scales, rates.log_scales,
       RunawayBound(initial.log_scales, 1)},
      {"the Gaussians' rotations", "the rotation learning rate", flags.quats,
       rates.quats, RunawayBound(initial.quats, 1)},
      {"the Gaussians' opacity logits", "the opacity learning rate",
       flags.opacity, rates.opacity, RunawayBound(initial.opacity_logits, 1)},
      {"the Gaussians' SH colours", "an SH learning rate", flags.sh,
       std::max(rates.sh_dc, rates.sh_rest), RunawayBound(initial.sh, 1)},
      {"the Gaussians' dynamic logits", "the dynamic-logit learning rate",
       flags.dynamic, rates.dynamic, RunawayBound(initial.dynamic_logits, 1)},
  };
}

std::vector<double> SplatMagnitudes(const GaussianSet& g) {
  std::vector<double> magnitudes;
  for (const GaussianArray& a : kGaussianArrays)
    magnitudes.push_back(MaxMagnitude(g.*a.values));
  return magnitudes;
}

}  // namespace es
