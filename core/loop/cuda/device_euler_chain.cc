#include "core/loop/cuda/device_euler_chain.h"

#include "core/loop/cuda/euler_kernels.h"

namespace es {
namespace cuda {

void DeviceEulerChain::Forward(const FieldParams& params, int n,
                               const double* x0, const int* steps,
                               double* x_out) {
  Schedule(n, steps);
  order_.Upload(schedule_.order);
  const std::vector<int>& active = schedule_.active;
  const std::vector<size_t>& offset = schedule_.offset;
  const int max_steps = schedule_.max_steps;
  trajectory_.Resize(offset[max_steps]);
  velocities_.Resize(offset[max_steps]);

  counters_.Resize(2);
  counters_.Zero();
  const int first = max_steps > 0 ? active[0] : 0;
  EulerStartKernel(n, first, order_.data(), x0, trajectory_.data(), x_out);
  const double limit = max_step();
  for (int s = 0; s < max_steps; ++s) {
    const int m = active[s];
    const int m_next = s + 1 < max_steps ? active[s + 1] : 0;
    const double* xs = trajectory_.data() + offset[s];
    double* velocity = velocities_.data() + offset[s];
    field_->Evaluate(params, m, xs, velocity, StepWorkspace(s));
    stats_.velocity_evaluations += m;
    double* next =
        s + 1 < max_steps ? trajectory_.data() + offset[s + 1] : nullptr;
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
  const std::vector<int>& active = schedule_.active;
  const std::vector<size_t>& offset = schedule_.offset;
  gradient_.Resize(3 * static_cast<size_t>(n_));
  EulerGatherKernel(n_, order_.data(), d_x_out, gradient_.data());
  const double limit = max_step();
  // x_{s+1} = x_s + c(V(x_s)): g_s = g_{s+1} + dV^T J_c^T g_{s+1}; V's
  // backward adds its dL/dx straight into the first m rows of g.
  for (int s = static_cast<int>(active.size()) - 1; s >= 0; --s) {
    const int m = active[s];
    const double* xs = trajectory_.data() + offset[s];
    const double* velocity = velocities_.data() + offset[s];
    DeviceFieldWorkspace* ws = StepWorkspace(s);
    if (s >= schedule_.kept_steps) {
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
