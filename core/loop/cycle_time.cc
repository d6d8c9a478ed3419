#include "core/loop/cycle_time.h"

#include <random>

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

std::vector<int> RandomStartTimes(int n, int cycle_length, uint32_t seed) {
  CHECK_GT(cycle_length, 0);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> uniform(0, cycle_length - 1);
  std::vector<int> times(n);
  for (int& t : times) t = uniform(rng);
  return times;
}

}  // namespace es
