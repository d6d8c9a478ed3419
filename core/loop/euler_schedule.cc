#include "core/loop/euler_schedule.h"

#include <algorithm>

#include <glog/logging.h>

namespace es {

EulerSchedule ScheduleEulerSteps(int n, const int* steps,
                                 size_t activation_bytes_per_point,
                                 size_t max_kept_bytes) {
  EulerSchedule out;
  int& max_steps = out.max_steps;
  for (int k = 0; k < n; ++k) {
    CHECK_GE(steps[k], 0) << "negative step count of point " << k;
    max_steps = std::max(max_steps, steps[k]);
  }
  // Counting sort by step count, largest first.
  std::vector<int> count(max_steps + 2, 0);
  for (int k = 0; k < n; ++k) ++count[max_steps - steps[k] + 1];
  for (int s = 1; s <= max_steps + 1; ++s) count[s] += count[s - 1];
  out.order.resize(n);
  for (int k = 0; k < n; ++k) out.order[count[max_steps - steps[k]]++] = k;
  out.active.assign(max_steps, 0);
  for (int k = 0; k < n; ++k) {
    for (int s = 0; s < steps[k]; ++s) ++out.active[s];
  }
  out.offset.assign(max_steps + 1, 0);
  for (int s = 0; s < max_steps; ++s) {
    out.offset[s + 1] = out.offset[s] + 3 * static_cast<size_t>(out.active[s]);
  }
  for (size_t bytes = 0; out.kept_steps < max_steps; ++out.kept_steps) {
    bytes += activation_bytes_per_point * out.active[out.kept_steps];
    if (bytes > max_kept_bytes) break;
  }
  return out;
}

size_t ActivationBytesPerPoint(int input_dim, int width, int depth,
                               int output_dim) {
  return sizeof(double) * (2 * static_cast<size_t>(input_dim) +
                           3 * static_cast<size_t>(depth) * width +
                           output_dim);
}

}  // namespace es
