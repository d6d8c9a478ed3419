#ifndef EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_
#define EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/gaussians.h"

namespace es {

// A training run that cannot go on: too many non-finite steps in a row,
// parameters that became non-finite, or values or a loss that grew by
// orders of magnitude. Apps print it and exit non-zero; the stage has
// written no model and its last checkpoint is the last good one.
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

// The largest |value| of values[0, n) (0 for none); +infinity if any is
// NaN or infinite, so one pass answers both "finite?" and "how large?".
double MaxMagnitude(const double* values, size_t n);
inline double MaxMagnitude(const std::vector<double>& values) {
  return MaxMagnitude(values.data(), values.size());
}

// x to three significant digits ("1e+30"), as divergence messages give
// values.
std::string FormatMagnitude(double x);

// How many times its starting scale a parameter block may grow before the
// run counts as diverged. Adam moves a value by about its learning rate
// per step, so a rate orders of magnitude too high (--lr_position 1e30)
// throws values this far in one step, while a normal run (rates <= 0.05,
// at most tens of thousands of steps) stays within a few thousand times.
constexpr double kRunawayGrowth = 1e6;
// How many times its scale a loss may grow (the scale a fit starts from):
// 1e3 times the RMSE of a squared loss.
constexpr double kLossGrowth = 1e6;

// One parameter block as the guard watches it for runaway values.
struct GuardedBlock {
  std::string name;           // "the Gaussians' means"
  std::string learning_rate;  // "the position learning rate"
  std::string flag;           // what sets it: "--lr_position"
  double rate = 0;            // its value
  double bound = 0;           // the largest |value| a healthy run reaches
};

// kRunawayGrowth x max(scale, the largest |value| of `initial`): a block's
// bound from its values at the start and a floor in its units (the scene
// extent for positions, 1 for values of order one).
double RunawayBound(const double* initial, size_t n, double scale);
inline double RunawayBound(const std::vector<double>& initial, double scale) {
  return RunawayBound(initial.data(), initial.size(), scale);
}

// Every trainer's guard against NaN/Inf and finite garbage. A step whose
// loss or gradient is not finite is skipped (no parameter update) and
// counted; `max_in_a_row` such steps in a row throw TrainingDiverged, since
// a state that keeps producing them will not recover. Parameters that are
// not finite after an update throw at once: every later step would be
// non-finite too. So do finite parameters beyond their block's bound
// (CheckRunaway) and a loss beyond kLossGrowth times its scale
// (CheckLoss): a run that went there renders or fits nothing (held-out
// PSNR 5.6 dB instead of 19.3), and the message names the learning rate
// to lower.
class DivergenceGuard {
 public:
  // `what` names the trainer in messages ("Stage 1 training", ...);
  // `outcome` ends them, saying what the stopped run left behind.
  explicit DivergenceGuard(
      std::string what, int max_in_a_row = 10,
      std::string outcome =
          "no model was written, the last checkpoint is kept");

  // True if a step with this loss and gradient may update the parameters.
  bool Accept(int64_t iteration, bool loss_and_gradient_finite);
  // Throws TrainingDiverged unless the parameters after `iteration` are
  // finite.
  void CheckParameters(int64_t iteration, bool parameters_finite) const;
  // Throws TrainingDiverged naming the block and its learning rate if
  // `magnitude` (MaxMagnitude of its values after `iteration`) exceeds
  // block.bound.
  void CheckRunaway(int64_t iteration, const GuardedBlock& block,
                    double magnitude) const;
  // CheckParameters, then CheckRunaway for each block: magnitudes[i] is
  // MaxMagnitude of blocks[i]'s values after `iteration`.
  void CheckBlocks(int64_t iteration, const std::vector<GuardedBlock>& blocks,
                   const std::vector<double>& magnitudes) const;
  // Throws TrainingDiverged naming the learning rates of `blocks` if the
  // loss of `iteration` exceeds kLossGrowth x `scale`.
  void CheckLoss(int64_t iteration, double loss, double scale,
                 const std::vector<GuardedBlock>& blocks) const;

  int64_t skipped() const { return skipped_; }
  int in_a_row() const { return in_a_row_; }

 private:
  std::string what_;
  std::string outcome_;
  int max_in_a_row_;
  int in_a_row_ = 0;
  int64_t skipped_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_DIVERGENCE_GUARD_H_
