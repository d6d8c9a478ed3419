#include "core/loop/cuda/device_euler_chain.h"

#include <algorithm>
#include <utility>

#include <glog/logging.h>

#include "core/loop/cuda/euler_kernels.h"

namespace es {
namespace cuda {

DeviceEulerChain::DeviceEulerChain(const DeviceMotionField* field,
                                   const EulerOptions& options)
    : field_(field), options_(options) {
  CHECK(field_ != nullptr);
  CHECK_GT(options_.max_step_fraction, 0.0);
}

double DeviceEulerChain::max_step() const {
  return options_.max_step_fraction * field_->box_diagonal();
}

void DeviceEulerChain::Forward(const FieldParams& params, int n,
                               const double* x0, const int* steps,
                               double* x_out) {
  n_ = n;
  stats_ = EulerStats();
  const DeviceMlp& mlp = field_->mlp();
  EulerSchedule schedule = ScheduleEulerSteps(
      n, steps,
      ActivationBytesPerPoint(mlp.input_dim(), mlp.width(), mlp.depth(),
                              mlp.output_dim()),
      options_.max_kept_activation_bytes);
  const int max_steps = schedule.max_steps;
  order_.Upload(schedule.order);
  active_ = std::move(schedule.active);
  offset_ = std::move(schedule.offset);
  kept_steps_ = schedule.kept_steps;
  trajectory_.Resize(offset_[max_steps]);
  velocities_.Resize(offset_[max_steps]);
  if (static_cast<int>(step_workspaces_.size()) < kept_steps_)
    step_workspaces_.resize(kept_steps_);

  counters_.Resize(2);
  counters_.Zero();
  const int first = max_steps > 0 ? active_[0] : 0;
  EulerStartKernel(n, first, order_.data(), x0, trajectory_.data(), x_out);
  const double limit = max_step();
  for (int s = 0; s < max_steps; ++s) {
    const int m = active_[s];
    const int m_next = s + 1 < max_steps ? active_[s + 1] : 0;
    const double* xs = trajectory_.data() + offset_[s];
    double* velocity = velocities_.data() + offset_[s];
    field_->Evaluate(params, m, xs, velocity,
                     s < kept_steps_ ? &step_workspaces_[s] : &workspace_);
    stats_.velocity_evaluations += m;
    double* next =
        s + 1 < max_steps ? trajectory_.data() + offset_[s + 1] : nullptr;
    EulerStepKernel(m, m_next, order_.data(), xs, velocity, limit, next,
                    x_out, counters_.data());
  }
  unsigned long long counts[2];
  counters_.Download(counts);
  stats_.clamped_steps = static_cast<int64_t>(counts[kClampedSteps]);
  stats_.nonfinite_velocities =
      static_cast<int64_t>(counts[kNonFiniteVelocities]);
}

void DeviceEulerChain::Backward(const FieldParams& params,
                                const double* d_x_out,
                                const FieldGradients& grads, double* d_x0) {
  gradient_.Resize(3 * static_cast<size_t>(n_));
  EulerGatherKernel(n_, order_.data(), d_x_out, gradient_.data());
  const double limit = max_step();
  // x_{s+1} = x_s + c(V(x_s)): g_s = g_{s+1} + dV^T J_c^T g_{s+1}; V's
  // backward adds its dL/dx straight into the first m rows of g.
  for (int s = static_cast<int>(active_.size()) - 1; s >= 0; --s) {
    const int m = active_[s];
    const double* xs = trajectory_.data() + offset_[s];
    const double* velocity = velocities_.data() + offset_[s];
    DeviceFieldWorkspace* ws =
        s < kept_steps_ ? &step_workspaces_[s] : &workspace_;
    if (s >= kept_steps_) {
      // Dropped for memory: evaluate again for the activations.
      velocity_.Resize(3 * static_cast<size_t>(m));
      field_->Evaluate(params, m, xs, velocity_.data(), ws);
    }
    step_gradient_.Resize(3 * static_cast<size_t>(m));
    EulerStepBackwardKernel(m, velocity, limit, gradient_.data(),
                            step_gradient_.data());
    field_->Backward(params, step_gradient_.data(), grads, gradient_.data(),
                     ws);
  }
  if (d_x0 != nullptr) {
    EulerScatterAddKernel(n_, order_.data(), gradient_.data(), d_x0);
  }
}

}  // namespace cuda
}  // namespace es
