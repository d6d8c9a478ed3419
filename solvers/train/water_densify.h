#ifndef EULERSPLAT_SOLVERS_TRAIN_WATER_DENSIFY_H_
#define EULERSPLAT_SOLVERS_TRAIN_WATER_DENSIFY_H_

#include <cstdint>
#include <random>
#include <vector>

#include "core/loop/loop_model.h"
#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"

namespace es {

// Densification of the water during joint training. The static stage's
// water is a few large time-averaged blobs; where the images disagree with
// them most (view-space gradient of the advected splats), they are split
// into two smaller ones or cloned, so V carries finer structure. Ranked by
// a fraction of the water, not a gradient threshold, so the setting does
// not depend on the scene's loss scale.
struct WaterDensifyOptions {
  int interval = 0;        // every this many iterations (first half); 0: off
  double fraction = 0.2;   // of the water Gaussians, highest gradient first
  // Budget: at most this many times the water Gaussians joint training
  // started with (the Euler chain's cost grows with their number).
  double max_growth = 3.0;
  int views = 8;           // training frames whose gradients rank them
  // Larger than this on screen (std dev, px): split into two children at
  // 1 / 1.6 the size; else cloned at its size.
  double split_pixels = 1.0;
  // Children draw their own start times (with random starts on). Inherited
  // ones pile up: a lineage densified again and again shares one phase, so
  // its wraps from the last cycle index to the first all fall on one frame
  // step, the loop's seam when that phase is 0.
  bool fresh_start_times = true;
};

// The `fraction` of the water Gaussians with the highest mean view-space
// gradient (`mean_grad` per entry of `dynamic_index`; 0 when never seen:
// never picked), at most `max_dynamic - dynamic_index.size()` of them, as
// Gaussian indices in decreasing gradient order.
std::vector<int> PickWaterToDensify(const std::vector<int>& dynamic_index,
                                    const std::vector<double>& mean_grad,
                                    double fraction, int max_dynamic);

struct WaterDensifyResult {
  int split = 0;
  int cloned = 0;
};

// Densifies the picked Gaussians of `model`: one whose largest scale
// exceeds split_scale[k] is replaced by two children drawn from its own
// normal distribution with scales divided by 1.6; a smaller one stays and
// gains a clone drawn the same way at its size. Children are appended
// (water, with a start time drawn uniformly in [0, child_cycle_length)
// from rng, or the parent's where child_cycle_length is 0); the model's
// dynamic_index stays sorted and is remapped with its start_times; Adam
// moments follow, new ones at zero. The fields are left alone.
WaterDensifyResult DensifyWater(const std::vector<int>& picked,
                                const std::vector<double>& split_scale,
                                int child_cycle_length, std::mt19937_64* rng,
                                LoopModel* model, GaussianAdam* adam);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_WATER_DENSIFY_H_
