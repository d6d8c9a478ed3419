#include "core/base/schedule_simulation.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>

#include <glog/logging.h>

namespace es {

double DynamicScheduleMakespan(const std::vector<double>& costs, int threads,
                               int chunk) {
  CHECK_GE(threads, 1);
  CHECK_GE(chunk, 1);
  // (time the thread is free, thread id), earliest first.
  using Slot = std::pair<double, int>;
  std::priority_queue<Slot, std::vector<Slot>, std::greater<Slot>> free;
  for (int t = 0; t < threads; ++t) free.push({0.0, t});
  double makespan = 0;
  const size_t n = costs.size();
  for (size_t begin = 0; begin < n; begin += chunk) {
    Slot slot = free.top();
    free.pop();
    for (size_t i = begin; i < std::min(n, begin + chunk); ++i)
      slot.first += costs[i];
    makespan = std::max(makespan, slot.first);
    free.push(slot);
  }
  return makespan;
}

double StaticScheduleMakespan(const std::vector<double>& costs, int threads,
                              int chunk) {
  CHECK_GE(threads, 1);
  const size_t n = costs.size();
  std::vector<double> busy(threads, 0.0);
  if (chunk <= 0) {
    // OpenMP's static split: the first n % threads threads get one more.
    const size_t base = n / threads, extra = n % threads;
    size_t i = 0;
    for (int t = 0; t < threads; ++t) {
      const size_t count = base + (static_cast<size_t>(t) < extra ? 1 : 0);
      for (size_t k = 0; k < count; ++k) busy[t] += costs[i++];
    }
  } else {
    for (size_t i = 0; i < n; ++i) busy[(i / chunk) % threads] += costs[i];
  }
  return *std::max_element(busy.begin(), busy.end());
}

}  // namespace es
