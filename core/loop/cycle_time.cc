#include "core/loop/cycle_time.h"

#include <glog/logging.h>

namespace es {

int CycleIndex(int frame, int start_time, int cycle_length) {
  CHECK_GT(cycle_length, 0);
  const int r = (frame - start_time) % cycle_length;
  return r < 0 ? r + cycle_length : r;
}

int CycleNumber(int frame, int start_time, int cycle_length) {
  CHECK_GT(cycle_length, 0);
  const int d = frame - start_time;
  const int q = d / cycle_length;
  return (d % cycle_length < 0) ? q - 1 : q;
}

int DrawStartTime(int cycle_length, std::mt19937_64* rng) {
  CHECK_GT(cycle_length, 0);
  return static_cast<int>((*rng)() % static_cast<uint64_t>(cycle_length));
}

std::vector<int> RandomStartTimes(int n, int cycle_length, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<int> times(n);
  for (int& t : times) t = DrawStartTime(cycle_length, &rng);
  return times;
}

}  // namespace es
