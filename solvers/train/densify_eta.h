#ifndef EULERSPLAT_SOLVERS_TRAIN_DENSIFY_ETA_H_
#define EULERSPLAT_SOLVERS_TRAIN_DENSIFY_ETA_H_

#include <cstdint>

namespace es {

// What a Stage-1 progress line knows when it estimates the time left.
struct DensifyEtaInput {
  int64_t iteration = 0;             // done so far
  int64_t iterations = 0;            // the run's total
  double seconds_per_iteration = 0;  // measured over the last log window
  double gaussians = 0;              // at the end of that window
  double growth_per_iteration = 0;   // Gaussians added per iteration there
  int64_t densify_end = 0;  // no Gaussians are added from this iteration on
  double max_gaussians = 0;
};

// Seconds left, for an iteration whose cost is proportional to the number
// of Gaussians: while densification still adds Gaussians (before
// densify_end), they are projected to keep growing at the measured rate (a
// negative rate, from pruning, counts as none), capped at max_gaussians;
// after it their number stays put. A plain remaining x seconds-per-iteration
// estimate undershoots badly early in a densifying run.
double DensifyingEta(const DensifyEtaInput& in);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_DENSIFY_ETA_H_
