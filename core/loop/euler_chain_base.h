#ifndef EULERSPLAT_CORE_LOOP_EULER_CHAIN_BASE_H_
#define EULERSPLAT_CORE_LOOP_EULER_CHAIN_BASE_H_

#include <vector>

#include <glog/logging.h>

#include "core/loop/euler_schedule.h"

namespace es {

// What EulerChain and its device twin share: the field, the options, the
// last Forward's counts and schedule, and V's workspaces (one per kept
// step, one for the steps evaluated again in Backward). `Field` is
// MotionField or cuda::DeviceMotionField, `Workspace` its workspace type.
template <class Field, class Workspace>
class EulerChainBase {
 public:
  // Counts of the last Forward.
  const EulerStats& stats() const { return stats_; }
  double max_step() const {
    return options_.max_step_fraction * field_->box_diagonal();
  }

 protected:
  EulerChainBase(const Field* field, const EulerOptions& options)
      : field_(field), options_(options) {
    CHECK(field_ != nullptr);
    CHECK_GT(options_.max_step_fraction, 0.0);
  }

  // Starts a Forward of n points taking steps[k] steps: resets the counts,
  // lays out the batches and grows the kept steps' workspaces.
  void Schedule(int n, const int* steps) {
    n_ = n;
    stats_ = EulerStats();
    const auto& mlp = field_->mlp();
    schedule_ = ScheduleEulerSteps(
        n, steps,
        ActivationBytesPerPoint(mlp.input_dim(), mlp.width(), mlp.depth(),
                                mlp.output_dim()),
        options_.max_kept_activation_bytes);
    if (static_cast<int>(step_workspaces_.size()) < schedule_.kept_steps)
      step_workspaces_.resize(schedule_.kept_steps);
  }

  // V's workspace of step s: its own while within the kept budget, else
  // the shared one (Backward evaluates those steps again).
  Workspace* StepWorkspace(int s) {
    return s < schedule_.kept_steps ? &step_workspaces_[s] : &workspace_;
  }

  const Field* field_;
  EulerOptions options_;
  EulerStats stats_;
  int n_ = 0;
  EulerSchedule schedule_;
  std::vector<Workspace> step_workspaces_;  // only grows
  Workspace workspace_;  // the steps past schedule_.kept_steps
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_EULER_CHAIN_BASE_H_
