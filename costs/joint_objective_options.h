#ifndef EULERSPLAT_COSTS_JOINT_OBJECTIVE_OPTIONS_H_
#define EULERSPLAT_COSTS_JOINT_OBJECTIVE_OPTIONS_H_

// What Stage 3's objective sums, shared by the CPU JointObjective
// (costs/joint_objective.h) and its device twin
// (costs/cuda/device_joint_objective.h), and the unweighted terms one
// evaluation reports.

#include <cstdint>

#include "core/loop/euler_chain.h"
#include "core/render/rasterizer.h"
#include "costs/joint_render_cost.h"
#include "costs/water_energy_loss.h"
#include "costs/water_texture_loss.h"

namespace es {

struct JointObjectiveOptions {
  // Each rendered frame's fit: photometric, mask BCE, D's L2.
  JointRenderTerms terms;
  // The CPU's render options; the device twin takes their background and
  // renders in float, as its costs do.
  RenderOptions render;
  EulerOptions euler;
  // The pair terms (either on: the frame's neighbour is rendered too).
  WaterEnergyOptions water_energy;
  WaterTextureOptions water_texture;
  // > 0: the frame as the loop plays it (cycle number 0), scored by
  // WaterTextureLoss with water_texture's bands at this weight.
  double loop_texture_weight = 0;
  // >= 1: the loop texture term runs only on iterations that are
  // multiples of this, at its weight times it: the same expected gradient
  // for 1/K of its cost (1: every iteration, as before).
  int loop_texture_interval = 1;
  // The water losses read the frames' masks (else every pixel is water).
  bool water_masks = false;

  bool energy_on() const {
    return water_energy.motion_weight > 0 || water_energy.detail_weight > 0;
  }
  bool texture_on() const { return water_texture.weight > 0; }
  bool pair_on() const { return energy_on() || texture_on(); }
  bool loop_texture_on() const { return loop_texture_weight > 0; }
  // Whether the run's iteration `iteration` scores the loop's texture.
  bool loop_texture_due(int64_t iteration) const {
    return loop_texture_on() && iteration % loop_texture_interval == 0;
  }
  // The weight it enters those iterations' loss with.
  double loop_texture_step_weight() const {
    return loop_texture_weight * loop_texture_interval;
  }
  // The loop texture term's WaterTextureLoss (at the step weight).
  WaterTextureOptions loop_texture() const {
    WaterTextureOptions t = water_texture;
    t.weight = loop_texture_step_weight();
    return t;
  }
};

// The loop texture render's cost terms: the texture loss's image gradient
// is its only one.
JointRenderTerms ImageGradientOnlyTerms();

// The random directions of the texture terms at a draw (the trainers pass
// their iteration): the pair's are 2 i and 2 i + 1, the loop's apart from
// them, so a resumed run sees the same ones.
uint64_t PairTextureDraw(int64_t draw, int frame_of_pair);
uint64_t LoopTextureDraw(int64_t draw);

// One evaluation's terms, unweighted (the loss is their weighted sum).
struct JointObjectiveTerms {
  // Of the frame, or the pair's mean.
  double photometric = 0;
  double mask = 0;
  double residual = 0;
  WaterEnergyTerms energy;
  double texture = 0;       // the pair's mean
  double loop_texture = 0;  // of the loop's frame
  double flow_prior = 0;    // weighted (the prior's weight decays)
  EulerStats euler;         // the frame's composition
};

// A pair texture term's report: `sum` of the weighted, ramped values of
// `frames` renders back to the unramped mean (0 where the ramp is 0).
double UnrampedMean(double sum, int frames, double ramp, double weight);

}  // namespace es

#endif  // EULERSPLAT_COSTS_JOINT_OBJECTIVE_OPTIONS_H_
