#ifndef EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_
#define EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/gaussians.h"

namespace es {

// A training run that cannot go on: too many non-finite steps in a row, or
// parameters that became non-finite. Apps print it and exit non-zero; the
// stage has written no model and its last checkpoint is the last good one.
class TrainingDiverged : public std::runtime_error {
 public:
  explicit TrainingDiverged(const std::string& message)
      : std::runtime_error(message) {}
};

bool AllFinite(const double* values, size_t n);
inline bool AllFinite(const std::vector<double>& values) {
  return AllFinite(values.data(), values.size());
}
bool AllFinite(const GaussianSet& g);

// Every trainer's guard against NaN/Inf. A step whose loss or gradient is
// not finite is skipped (no parameter update) and counted; `max_in_a_row`
// such steps in a row throw TrainingDiverged, since a state that keeps
// producing them will not recover. Parameters that are not finite after an
// update throw at once: every later step would be non-finite too.
class DivergenceGuard {
 public:
  // `what` names the trainer in messages ("Stage 1", "V pretraining", ...).
  explicit DivergenceGuard(std::string what, int max_in_a_row = 10);

  // True if a step with this loss and gradient may update the parameters.
  bool Accept(int64_t iteration, bool loss_and_gradient_finite);
  // Throws TrainingDiverged unless the parameters after `iteration` are
  // finite.
  void CheckParameters(int64_t iteration, bool parameters_finite) const;

  int64_t skipped() const { return skipped_; }
  int in_a_row() const { return in_a_row_; }

 private:
  std::string what_;
  int max_in_a_row_;
  int in_a_row_ = 0;
  int64_t skipped_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_
