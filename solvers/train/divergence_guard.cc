#include "solvers/train/divergence_guard.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include <glog/logging.h>

namespace es {

bool AllFinite(const double* values, size_t n) {
  // x * 0 is 0 for every finite x and NaN for NaN and Inf: one branch-free
  // pass, with eight partial sums so it vectorizes (one running sum would
  // have to be added in order).
  double part[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (int l = 0; l < 8; ++l) part[l] += values[i + l] * 0.0;
  double sum = 0;
  for (int l = 0; l < 8; ++l) sum += part[l];
  for (; i < n; ++i) sum += values[i] * 0.0;
  return std::isfinite(sum);
}

bool AllFinite(const GaussianSet& g) {
  for (const std::vector<double>* v : {&g.means, &g.log_scales, &g.quats,
                                       &g.opacity_logits, &g.sh,
                                       &g.dynamic_logits})
    if (!AllFinite(*v)) return false;
  return true;
}

DivergenceGuard::DivergenceGuard(std::string what, int max_in_a_row)
    : what_(std::move(what)), max_in_a_row_(max_in_a_row) {
  CHECK_GT(max_in_a_row_, 0);
}

bool DivergenceGuard::Accept(int64_t iteration, bool finite) {
  if (finite) {
    in_a_row_ = 0;
    return true;
  }
  ++skipped_;
  ++in_a_row_;
  LOG(WARNING) << what_ << ": non-finite loss or gradient at iteration "
               << iteration << "; step skipped (" << in_a_row_
               << " in a row, " << skipped_ << " in all)";
  if (in_a_row_ >= max_in_a_row_)
    throw TrainingDiverged(
        what_ + " diverged: " + std::to_string(in_a_row_) +
        " non-finite steps in a row up to iteration " +
        std::to_string(iteration) +
        " (learning rates too high, or degenerate input?); no model was "
        "written, the last checkpoint is kept");
  return false;
}

void DivergenceGuard::CheckParameters(int64_t iteration, bool finite) const {
  if (finite) return;
  throw TrainingDiverged(what_ + " diverged: parameters became non-finite at "
                         "iteration " + std::to_string(iteration) +
                         " (learning rates too high?); no model was "
                         "written, the last checkpoint is kept");
}

}  // namespace es
