#include "core/loop/euler_chain.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include <glog/logging.h>

#include "core/base/stage_profile.h"
#include "core/loop/safe_step.h"

namespace es {
namespace {

void Count(StepKind kind, EulerStats* stats) {
  if (kind == StepKind::kClamped) ++stats->clamped_steps;
  if (kind == StepKind::kNonFinite) ++stats->nonfinite_velocities;
}

}  // namespace

void TakeSafeStep(const double* v, double max_step, double* x,
                  EulerStats* stats) {
  double step[3];
  Count(SafeStep(v, max_step, step), stats);
  for (int j = 0; j < 3; ++j) x[j] += step[j];
}

EulerChain::EulerChain(const MotionField* field, const EulerOptions& options)
    : field_(field), options_(options) {
  CHECK(field_ != nullptr);
  CHECK_GT(options_.max_step_fraction, 0.0);
}

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

double EulerChain::max_step() const {
  return options_.max_step_fraction * field_->box_diagonal();
}

void EulerChain::Forward(const FieldParams& params, int n, const double* x0,
                         const int* steps, double* x_out) {
  ScopedStage timer(Stage::kEulerChain);
  n_ = n;
  stats_ = EulerStats();
  const Mlp& mlp = field_->mlp();
  EulerSchedule schedule = ScheduleEulerSteps(
      n, steps,
      ActivationBytesPerPoint(mlp.input_dim(), mlp.width(), mlp.depth(),
                              mlp.output_dim()),
      options_.max_kept_activation_bytes);
  const int max_steps = schedule.max_steps;
  order_ = std::move(schedule.order);
  active_ = std::move(schedule.active);
  offset_ = std::move(schedule.offset);
  kept_steps_ = schedule.kept_steps;
  trajectory_.resize(offset_[max_steps]);
  velocities_.resize(offset_[max_steps]);
  if (static_cast<int>(step_workspaces_.size()) < kept_steps_)
    step_workspaces_.resize(kept_steps_);

  const int first = max_steps > 0 ? active_[0] : 0;
  for (int k = 0; k < n; ++k) {
    const double* src = x0 + 3 * order_[k];
    double* dst = k < first ? &trajectory_[3 * k] : x_out + 3 * order_[k];
    std::copy(src, src + 3, dst);
  }
  const double limit = max_step();
  for (int s = 0; s < max_steps; ++s) {
    const int m = active_[s];
    const int m_next = s + 1 < max_steps ? active_[s + 1] : 0;
    const double* xs = &trajectory_[offset_[s]];
    double* velocity = &velocities_[offset_[s]];
    field_->Evaluate(params, m, xs, velocity,
                     s < kept_steps_ ? &step_workspaces_[s] : &workspace_);
    stats_.velocity_evaluations += m;
    for (int k = 0; k < m; ++k) {
      double step[3];
      Count(SafeStep(&velocity[3 * k], limit, step), &stats_);
      double* dst = k < m_next ? &trajectory_[offset_[s + 1] + 3 * k]
                               : x_out + 3 * order_[k];
      for (int j = 0; j < 3; ++j) dst[j] = xs[3 * k + j] + step[j];
    }
  }
}

void EulerChain::Backward(const FieldParams& params, const double* d_x_out,
                          const FieldGradients& grads, double* d_x0) {
  ScopedStage timer(Stage::kEulerChain);
  gradient_.resize(3 * static_cast<size_t>(n_));
  for (int k = 0; k < n_; ++k) {
    std::copy(d_x_out + 3 * order_[k], d_x_out + 3 * order_[k] + 3,
              &gradient_[3 * k]);
  }
  const double limit = max_step();
  // x_{s+1} = x_s + c(V(x_s)): g_s = g_{s+1} + dV^T J_c^T g_{s+1}.
  for (int s = static_cast<int>(active_.size()) - 1; s >= 0; --s) {
    const int m = active_[s];
    const double* xs = &trajectory_[offset_[s]];
    const double* velocity = &velocities_[offset_[s]];
    FieldWorkspace* ws =
        s < kept_steps_ ? &step_workspaces_[s] : &workspace_;
    if (s >= kept_steps_) {
      // Dropped for memory: evaluate again for the activations.
      velocity_.resize(3 * static_cast<size_t>(m));
      field_->Evaluate(params, m, xs, velocity_.data(), ws);
    }
    step_gradient_.resize(3 * static_cast<size_t>(m));
    for (int k = 0; k < m; ++k) {
      SafeStepBackward(&velocity[3 * k], limit, &gradient_[3 * k],
                       &step_gradient_[3 * k]);
    }
    d_x_.assign(3 * static_cast<size_t>(m), 0.0);
    field_->Backward(params, step_gradient_.data(), grads, d_x_.data(), ws);
    for (int i = 0; i < 3 * m; ++i) gradient_[i] += d_x_[i];
  }
  if (d_x0 == nullptr) return;
  for (int k = 0; k < n_; ++k) {
    for (int j = 0; j < 3; ++j) d_x0[3 * order_[k] + j] += gradient_[3 * k + j];
  }
}

}  // namespace es
