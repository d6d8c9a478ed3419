#include "core/loop/loop_animator.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/loop/cycle_time.h"

namespace es {

LoopAnimator::LoopAnimator(const MotionField* field,
                           const EulerOptions& options, int cycle_length)
    : field_(field),
      cycle_length_(cycle_length),
      chain_(field, options) {
  CHECK_GT(cycle_length_, 0);
}

void LoopAnimator::Start(const FieldParams& params, int n, const double* x0,
                         const std::vector<int>& start_times, int frame) {
  CHECK_EQ(static_cast<int>(start_times.size()), n);
  frame_ = frame;
  canonical_.assign(x0, x0 + 3 * static_cast<size_t>(n));
  cycle_index_.resize(n);
  for (int k = 0; k < n; ++k) {
    CHECK(start_times[k] >= 0 && start_times[k] < cycle_length_);
    cycle_index_[k] = CycleIndex(frame, start_times[k], cycle_length_);
  }
  positions_.resize(3 * static_cast<size_t>(n));
  chain_.Forward(params, n, x0, cycle_index_.data(), positions_.data());
  stats_ = chain_.stats();
}

void LoopAnimator::Advance(const FieldParams& params) {
  const int n = static_cast<int>(cycle_index_.size());
  ++frame_;
  // One batch over all points; the wrapping ones (1 in L) ignore theirs.
  velocity_.resize(3 * static_cast<size_t>(n));
  field_->Evaluate(params, n, positions_.data(), velocity_.data(), &workspace_);
  stats_.velocity_evaluations += n;
  const double limit = chain_.max_step();
  for (int k = 0; k < n; ++k) {
    double* x = &positions_[3 * k];
    if (++cycle_index_[k] == cycle_length_) {
      cycle_index_[k] = 0;
      std::copy(&canonical_[3 * k], &canonical_[3 * k] + 3, x);
      continue;
    }
    TakeSafeStep(&velocity_[3 * k], limit, x, &stats_);
  }
}

}  // namespace es
