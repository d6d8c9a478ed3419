#ifndef EULERSPLAT_CORE_BASE_ITERATION_PARTS_H_
#define EULERSPLAT_CORE_BASE_ITERATION_PARTS_H_

// The trainers' --profile by what a user waits for: the stages of
// stage_profile.h grouped into the parts of a training iteration (the fit's
// render, the loop's second render, fields, Euler chain, backward, Adam,
// densification, evaluation, ...). Every stage of every pass belongs to
// exactly one part, so the parts add up to the profiled wall time.

#include <string>

#include "core/base/stage_profile.h"

namespace es {

enum class Part : int {
  kFitRender = 0,     // fit pass: projection, sorting, tiles, composition
  kLosses,            // fit pass: L1, SSIM, BCE, residual, water losses
  kLoopTextureRender, // the loop's second render and its texture loss
  kFields,            // V and D, forward and backward, every pass
  kEulerChain,        // Alg. 1, forward and backward, every pass
  kBackward,          // the rasterizer's backward, every pass
  kAdam,
  kFlowPrior,         // the scene-flow prior
  kDensification,     // statistics, densify + prune, their renders
  kEvaluation,        // held-out evaluations, their renders
  kCheckpoint,        // checkpoints and history rows
  kRanks,             // data-parallel: waiting for ranks and the allreduce
  kOther,             // the iterations' untimed remainder (and setup)
  kNumParts
};

const char* PartName(Part part);

// The part a stage's time in `pass` belongs to.
Part PartOf(Pass pass, Stage stage);

// Seconds charged to `part` since the profile started.
double PartSeconds(const StageProfile& profile, Part part);

// One row per part with time: seconds in all, ms per iteration, share;
// then the loop texture pass in all (its fields, chain and backward too).
std::string PartsTable(const StageProfile& profile);

// Prints StageProfile's table and the parts table (if profiling), then
// stops the profile: the trainers' end of --profile.
void PrintProfileAndStop(const std::string& title);

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_ITERATION_PARTS_H_
