#ifndef EULERSPLAT_CORE_BASE_LR_SCHEDULE_H_
#define EULERSPLAT_CORE_BASE_LR_SCHEDULE_H_

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace es {

// Log-linear decay from `initial` at step 0 to `final` at `max_steps`, held
// there afterwards (3DGS's position schedule).
inline double LogLinearLr(double initial, double final, int64_t step,
                          int64_t max_steps) {
  if (max_steps <= 0 || initial <= 0 || final <= 0) return initial;
  const double t = std::clamp(static_cast<double>(step) / max_steps, 0.0, 1.0);
  return std::exp(std::log(initial) * (1 - t) + std::log(final) * t);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_LR_SCHEDULE_H_
