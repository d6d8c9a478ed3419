#ifndef EULERSPLAT_CORE_BASE_SCHEDULE_SIMULATION_H_
#define EULERSPLAT_CORE_BASE_SCHEDULE_SIMULATION_H_

// How a parallel loop's work would split over more threads than the
// machine has: the loop's per-iteration costs (measured or modelled on one
// thread) handed out as an OpenMP schedule hands them out, with no
// scheduling overhead and no memory contention, so the figures are upper
// bounds on the speedup.

#include <vector>

namespace es {

// The finishing time of the last thread when `threads` threads run the
// iterations with costs[i] under schedule(dynamic, chunk): chunks of
// `chunk` consecutive iterations, in order, each to the thread that is
// free first (the lowest-numbered among ties).
double DynamicScheduleMakespan(const std::vector<double>& costs, int threads,
                               int chunk = 1);

// The same under schedule(static, chunk): chunk c goes to thread
// c % threads (chunk <= 0: one contiguous block per thread, as
// schedule(static)).
double StaticScheduleMakespan(const std::vector<double>& costs, int threads,
                              int chunk = 0);

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_SCHEDULE_SIMULATION_H_
