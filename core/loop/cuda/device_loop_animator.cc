#include "core/loop/cuda/device_loop_animator.h"

#include <glog/logging.h>

#include "core/loop/cuda/euler_kernels.h"
#include "core/loop/cycle_time.h"

namespace es {
namespace cuda {

DeviceLoopAnimator::DeviceLoopAnimator(const DeviceMotionField* field,
                                       const EulerOptions& options,
                                       int cycle_length)
    : field_(field), cycle_length_(cycle_length), chain_(field, options) {
  CHECK_GT(cycle_length_, 0);
}

void DeviceLoopAnimator::Start(const FieldParams& params, int n,
                               const double* x0,
                               const std::vector<int>& start_times,
                               int frame) {
  CHECK_EQ(static_cast<int>(start_times.size()), n);
  frame_ = frame;
  n_ = n;
  const size_t size = 3 * static_cast<size_t>(n);
  canonical_.Resize(size);
  CopyDoublesKernel(static_cast<long long>(size), x0, canonical_.data());
  std::vector<int> cycle_index(n);
  for (int k = 0; k < n; ++k) {
    CHECK(start_times[k] >= 0 && start_times[k] < cycle_length_)
        << "start time " << start_times[k] << " of Gaussian " << k
        << " is outside [0, " << cycle_length_ << ")";
    cycle_index[k] = CycleIndex(frame, start_times[k], cycle_length_);
  }
  cycle_index_.Upload(cycle_index);
  positions_.Resize(size);
  chain_.Forward(params, n, canonical_.data(), cycle_index.data(),
                 positions_.data());
  start_stats_ = chain_.stats();
  advanced_ = 0;
  counters_.Resize(2);
  counters_.Zero();
}

void DeviceLoopAnimator::Advance(const FieldParams& params) {
  ++frame_;
  // One batch over all points; the wrapping ones (1 in L) ignore theirs.
  velocity_.Resize(3 * static_cast<size_t>(n_));
  field_->Evaluate(params, n_, positions_.data(), velocity_.data(),
                   &workspace_);
  advanced_ += n_;
  EulerAdvanceKernel(n_, cycle_length_, velocity_.data(), chain_.max_step(),
                     canonical_.data(), positions_.data(),
                     cycle_index_.data(), counters_.data());
}

EulerStats DeviceLoopAnimator::stats() const {
  EulerStats stats = start_stats_;
  stats.velocity_evaluations += advanced_;
  if (counters_.size() == 2) {
    unsigned long long counts[2];
    counters_.Download(counts);
    stats.clamped_steps += static_cast<int64_t>(counts[kClampedSteps]);
    stats.nonfinite_velocities +=
        static_cast<int64_t>(counts[kNonFiniteVelocities]);
  }
  return stats;
}

}  // namespace cuda
}  // namespace es
