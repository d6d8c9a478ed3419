#include "core/loop/euler_chain.h"

#include <algorithm>

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

void EulerChain::Forward(const FieldParams& params, int n, const double* x0,
                         const int* steps, double* x_out) {
  ScopedStage timer(Stage::kEulerChain);
  Schedule(n, steps);
  const std::vector<int>& order = schedule_.order;
  const std::vector<int>& active = schedule_.active;
  const std::vector<size_t>& offset = schedule_.offset;
  const int max_steps = schedule_.max_steps;
  trajectory_.resize(offset[max_steps]);
  velocities_.resize(offset[max_steps]);

  const int first = max_steps > 0 ? active[0] : 0;
  for (int k = 0; k < n; ++k) {
    const double* src = x0 + 3 * order[k];
    double* dst = k < first ? &trajectory_[3 * k] : x_out + 3 * order[k];
    std::copy(src, src + 3, dst);
  }
  const double limit = max_step();
  for (int s = 0; s < max_steps; ++s) {
    const int m = active[s];
    const int m_next = s + 1 < max_steps ? active[s + 1] : 0;
    const double* xs = &trajectory_[offset[s]];
    double* velocity = &velocities_[offset[s]];
    field_->Evaluate(params, m, xs, velocity, StepWorkspace(s));
    stats_.velocity_evaluations += m;
    for (int k = 0; k < m; ++k) {
      double step[3];
      Count(SafeStep(&velocity[3 * k], limit, step), &stats_);
      double* dst = k < m_next ? &trajectory_[offset[s + 1] + 3 * k]
                               : x_out + 3 * order[k];
      for (int j = 0; j < 3; ++j) dst[j] = xs[3 * k + j] + step[j];
    }
  }
}

void EulerChain::Backward(const FieldParams& params, const double* d_x_out,
                          const FieldGradients& grads, double* d_x0) {
  ScopedStage timer(Stage::kEulerChain);
  const std::vector<int>& order = schedule_.order;
  const std::vector<int>& active = schedule_.active;
  const std::vector<size_t>& offset = schedule_.offset;
  gradient_.resize(3 * static_cast<size_t>(n_));
  for (int k = 0; k < n_; ++k) {
    std::copy(d_x_out + 3 * order[k], d_x_out + 3 * order[k] + 3,
              &gradient_[3 * k]);
  }
  const double limit = max_step();
  // x_{s+1} = x_s + c(V(x_s)): g_s = g_{s+1} + dV^T J_c^T g_{s+1}.
  for (int s = static_cast<int>(active.size()) - 1; s >= 0; --s) {
    const int m = active[s];
    const double* xs = &trajectory_[offset[s]];
    const double* velocity = &velocities_[offset[s]];
    FieldWorkspace* ws = StepWorkspace(s);
    if (s >= schedule_.kept_steps) {
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
    for (int j = 0; j < 3; ++j) d_x0[3 * order[k] + j] += gradient_[3 * k + j];
  }
}

}  // namespace es
