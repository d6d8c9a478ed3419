#ifndef EULERSPLAT_SOLVERS_TRAIN_DENSIFY_H_
#define EULERSPLAT_SOLVERS_TRAIN_DENSIFY_H_

#include <random>
#include <vector>

#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"

namespace es {

// Adaptive density control, 3DGS schedule and thresholds.
struct DensifyOptions {
  int from_iteration = 500;
  int until_iteration = 15000;  // and at most half of the run (trainer)
  int interval = 100;
  int opacity_reset_interval = 3000;  // only while densifying
  double grad_threshold = 2e-4;       // mean view-space (NDC) gradient norm
  double percent_dense = 0.01;        // clone below, split above this * extent
  double min_opacity = 0.005;
  double max_screen_radius = 20;  // px, after the first opacity reset
  // * extent, after the first opacity reset; 0: off. 3DGS prunes at 0.1,
  // but the extent is the cameras' spread, and a hand-held video's is
  // small next to its depth: 0.1 pruned most of the backdrop at every
  // step after the reset (held-out PSNR near 7 dB until densification
  // ended; 2.3 dB lower at the end on the fountain;
  // docs/results/stages-1-2.md).
  double max_world_scale = 0;
  int max_gaussians = 1000000;
};

// Per-Gaussian statistics gathered between densification steps.
class DensityStats {
 public:
  void Reset(int count);
  // Adds one rendered view from the rasterizer's outputs for it: `radii`
  // (N, px, 0 where culled; Rasterizer::Radii) and `mean2d_grads` (2N,
  // d loss / d projected mean in pixels; Rasterizer::Mean2dGradients). As
  // 3DGS, only Gaussians with a positive radius count, and the accumulated
  // view-space gradient is in NDC units: the pixel gradient times W/2, H/2.
  void AddView(int width, int height, const std::vector<int>& radii,
               const std::vector<double>& mean2d_grads);

  // Adds the statistics of other views of the same Gaussians (a batch's,
  // summed over the ranks): sums and counts add, radii take the largest.
  void Add(const DensityStats& views);

  void Filter(const std::vector<bool>& keep);
  void AppendZeros(int count);

  int size() const { return static_cast<int>(grad_sum.size()); }
  double MeanGrad(int i) const {
    return count[i] > 0 ? grad_sum[i] / count[i] : 0.0;
  }

  std::vector<double> grad_sum;    // sum of view-space gradient norms
  std::vector<double> count;       // views in which the Gaussian was visible
  std::vector<double> max_radius;  // largest screen radius seen (px)
};

struct DensifyResult {
  int cloned = 0;
  int split = 0;
  int pruned = 0;
};

// Clones small and splits large Gaussians whose mean view-space gradient
// reaches the threshold (highest first while under max_gaussians), then
// prunes transparent ones (and, when `prune_large`, ones too big on screen
// or in the world). Adam moments and stats follow the Gaussians; new ones
// start at zero. Resets the stats.
DensifyResult DensifyAndPrune(const DensifyOptions& options,
                              double scene_extent, bool prune_large,
                              std::mt19937_64* rng, GaussianSet* g,
                              GaussianAdam* adam, DensityStats* stats);

// Largest of a Gaussian's three scales (world units).
double MaxScale(const GaussianSet& g, int i);

// Appends to `added` a copy of g[i] moved to a point drawn from g[i]'s own
// normal distribution (3 draws of `normal`), every scale divided by
// `shrink`: the child of a 3DGS split (shrink 1.6) or clone (shrink 1).
void AppendSampledChild(const GaussianSet& g, int i, double shrink,
                        std::normal_distribution<double>* normal,
                        std::mt19937_64* rng, GaussianSet* added);

// Caps every opacity at `max_opacity` (3DGS: 0.01) and zeroes the opacity
// moments, so the optimizer re-learns which Gaussians are needed.
void ResetOpacity(double max_opacity, GaussianSet* g, GaussianAdam* adam);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_DENSIFY_H_
