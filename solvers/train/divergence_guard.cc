#include "solvers/train/divergence_guard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
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
  for (const GaussianArray& a : kGaussianArrays)
    if (!AllFinite(g.*a.values)) return false;
  return true;
}

double MaxMagnitude(const double* values, size_t n) {
  // With the sign bit cleared, the bits of a double order as its magnitude
  // does, infinity and NaN above every finite value: one integer maximum
  // answers both questions, in eight lanes so that it vectorizes.
  constexpr int64_t kNoSign = std::numeric_limits<int64_t>::max();
  int64_t lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    for (int l = 0; l < 8; ++l) {
      int64_t bits;
      std::memcpy(&bits, values + i + l, sizeof(bits));
      bits &= kNoSign;
      lane[l] = lane[l] < bits ? bits : lane[l];
    }
  }
  int64_t max = 0;
  for (int l = 0; l < 8; ++l) max = std::max(max, lane[l]);
  for (; i < n; ++i) {
    int64_t bits;
    std::memcpy(&bits, values + i, sizeof(bits));
    max = std::max(max, bits & kNoSign);
  }
  double magnitude;
  std::memcpy(&magnitude, &max, sizeof(magnitude));
  return std::isfinite(magnitude) ? magnitude
                                  : std::numeric_limits<double>::infinity();
}

double RunawayBound(const double* initial, size_t n, double scale) {
  return kRunawayGrowth * std::max(scale, MaxMagnitude(initial, n));
}

std::string FormatMagnitude(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", x);
  return text;
}

DivergenceGuard::DivergenceGuard(std::string what, int max_in_a_row,
                                 std::string outcome)
    : what_(std::move(what)),
      outcome_(std::move(outcome)),
      max_in_a_row_(max_in_a_row) {
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
        " (learning rates too high, or degenerate input?); " + outcome_);
  return false;
}

void DivergenceGuard::CheckParameters(int64_t iteration, bool finite) const {
  if (finite) return;
  throw TrainingDiverged(what_ + " diverged: parameters became non-finite at "
                         "iteration " + std::to_string(iteration) +
                         " (learning rates too high?); " + outcome_);
}

void DivergenceGuard::CheckRunaway(int64_t iteration,
                                   const GuardedBlock& block,
                                   double magnitude) const {
  if (magnitude <= block.bound) return;
  throw TrainingDiverged(
      what_ + " diverged at iteration " + std::to_string(iteration) +
      ": a value of " + block.name + " reached " + FormatMagnitude(magnitude) +
      " (limit " + FormatMagnitude(block.bound) + ", " + FormatMagnitude(kRunawayGrowth) +
      " times the block's scale at the start); " + block.learning_rate +
      " is too high (" + block.flag + " " + FormatMagnitude(block.rate) +
      "): lower it; " + outcome_);
}

void DivergenceGuard::CheckBlocks(int64_t iteration,
                                  const std::vector<GuardedBlock>& blocks,
                                  const std::vector<double>& magnitudes) const {
  CHECK_EQ(blocks.size(), magnitudes.size());
  bool finite = true;
  for (double m : magnitudes) finite = finite && std::isfinite(m);
  CheckParameters(iteration, finite);
  for (size_t b = 0; b < blocks.size(); ++b)
    CheckRunaway(iteration, blocks[b], magnitudes[b]);
}

void DivergenceGuard::CheckLoss(int64_t iteration, double loss, double scale,
                                const std::vector<GuardedBlock>& blocks) const {
  if (!(loss > kLossGrowth * scale)) return;
  std::string rates;
  for (const GuardedBlock& b : blocks)
    rates += (rates.empty() ? "" : ", ") + b.flag + " " + FormatMagnitude(b.rate);
  throw TrainingDiverged(
      what_ + " diverged at iteration " + std::to_string(iteration) +
      ": the loss reached " + FormatMagnitude(loss) + " (limit " +
      FormatMagnitude(kLossGrowth * scale) + ", " + FormatMagnitude(kLossGrowth) +
      " times its scale at the start); the learning rates are too high (" +
      rates + "): lower them; " + outcome_);
}

}  // namespace es
