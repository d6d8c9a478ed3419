#ifndef EULERSPLAT_CORE_LOOP_CYCLE_TIME_H_
#define EULERSPLAT_CORE_LOOP_CYCLE_TIME_H_

#include <cstdint>
#include <random>
#include <vector>

namespace es {

// Looping time. Dynamic Gaussian n starts its loop at frame t0_n in [0, L).
// At frame i it is at cycle index t = (i - t0_n) mod L, always in [0, L)
// even for i < t0_n, in cycle number p = floor((i - t0_n) / L), negative
// for i < t0_n.
int CycleIndex(int frame, int start_time, int cycle_length);
int CycleNumber(int frame, int start_time, int cycle_length);
// One start time uniform in [0, cycle_length) (up to a modulo bias of
// order cycle_length / 2^64). Our own reduction of the raw draw, since the
// standard distributions differ between standard libraries and a resumed
// run must replay identically.
int DrawStartTime(int cycle_length, std::mt19937_64* rng);
// n start times drawn as above from std::mt19937_64(seed).
std::vector<int> RandomStartTimes(int n, int cycle_length, uint64_t seed);

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CYCLE_TIME_H_
