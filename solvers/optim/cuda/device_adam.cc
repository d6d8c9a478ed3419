#include "solvers/optim/cuda/device_adam.h"

#include <glog/logging.h>

#include <utility>
#include <vector>

#include "core/model/gaussians.h"
#include "solvers/optim/cuda/adam_kernels.h"

namespace es {
namespace cuda {
namespace {

// AdamStep's constants (computed on the host by AdamStep itself).
AdamConstants Constants(const AdamOptions& options, int64_t t, double lr) {
  AdamConstants c;
  c.on = lr != 0;
  if (!c.on) return c;
  const AdamStep step(options, t, lr);
  c.beta1 = step.beta1;
  c.beta2 = step.beta2;
  c.eps = step.eps;
  c.step = step.step;
  c.inv_sqrt_bc2 = step.inv_sqrt_bc2;
  return c;
}

void Zeros(DeviceBuffer<double>* b, size_t n) {
  b->Resize(n);
  b->Zero();
}

void Fetch(const DeviceBuffer<double>& b, std::vector<double>* host) {
  host->resize(b.size());
  b.Download(host->data());
}

}  // namespace

void DeviceAdamUpdate(const AdamOptions& options, int64_t t, double lr,
                      int n, const double* grad, double* m, double* v,
                      double* x) {
  const AdamConstants c = Constants(options, t, lr);
  AdamUpdateKernel(n, 1, 1, c, c, grad, m, v, x);
}

void DeviceGaussianAdam::Reset(int count, int sh_degree) {
  count_ = count;
  sh_degree_ = sh_degree;
  const size_t n = count;
  const size_t sh = 3 * static_cast<size_t>(NumShCoeffs(sh_degree)) * n;
  for (Moments* mm : {&m_, &v_}) {
    Zeros(&mm->means, 3 * n);
    Zeros(&mm->log_scales, 3 * n);
    Zeros(&mm->quats, 4 * n);
    Zeros(&mm->opacity_logits, n);
    Zeros(&mm->sh, sh);
    Zeros(&mm->dynamic_logits, n);
  }
  step_ = 0;
}

void DeviceGaussianAdam::Step(const GaussianLearningRates& lr,
                              const DeviceGaussianBlocks& grad,
                              const DeviceGaussianBlocks& params) {
  CHECK_EQ(params.count, count_) << "moments out of sync";
  CHECK_EQ(params.sh_degree, sh_degree_) << "moments out of sync";
  CHECK_EQ(grad.count, count_);
  CHECK_EQ(grad.sh_degree, sh_degree_);
  ++step_;
  const long long n = count_;
  auto update = [&](double rate, long long size, const double* g,
                    DeviceBuffer<double>* mm, DeviceBuffer<double>* vv,
                    double* x) {
    if (size == 0) return;
    const AdamConstants c = Constants(options_, step_, rate);
    AdamUpdateKernel(size, 1, 1, c, c, g, mm->data(), vv->data(), x);
  };
  update(lr.means, 3 * n, grad.means, &m_.means, &v_.means, params.means);
  update(lr.log_scales, 3 * n, grad.log_scales, &m_.log_scales,
         &v_.log_scales, params.log_scales);
  update(lr.quats, 4 * n, grad.quats, &m_.quats, &v_.quats, params.quats);
  update(lr.opacity_logits, n, grad.opacity_logits, &m_.opacity_logits,
         &v_.opacity_logits, params.opacity_logits);
  update(lr.dynamic_logits, n, grad.dynamic_logits, &m_.dynamic_logits,
         &v_.dynamic_logits, params.dynamic_logits);
  // SH: per Gaussian 3 DC values, then the higher bands.
  const int width = 3 * NumShCoeffs(sh_degree_);
  AdamUpdateKernel(width * n, width, 3, Constants(options_, step_, lr.sh_dc),
                   Constants(options_, step_, lr.sh_rest), grad.sh,
                   m_.sh.data(), v_.sh.data(), params.sh);
}

void DeviceGaussianAdam::Download(GaussianSet* m, GaussianSet* v) const {
  for (auto [from, to] : {std::pair{&m_, m}, std::pair{&v_, v}}) {
    to->sh_degree = sh_degree_;
    Fetch(from->means, &to->means);
    Fetch(from->log_scales, &to->log_scales);
    Fetch(from->quats, &to->quats);
    Fetch(from->opacity_logits, &to->opacity_logits);
    Fetch(from->sh, &to->sh);
    Fetch(from->dynamic_logits, &to->dynamic_logits);
  }
}

GaussianAdamState DeviceGaussianAdam::State() const {
  GaussianAdamState state;
  Download(&state.m, &state.v);
  state.step = step_;
  return state;
}

void DeviceGaussianAdam::Restore(const GaussianAdamState& state) {
  state.m.CheckConsistent();
  CHECK_EQ(state.v.size(), state.m.size());
  CHECK_EQ(state.v.sh_degree, state.m.sh_degree);
  count_ = state.m.size();
  sh_degree_ = state.m.sh_degree;
  step_ = state.step;
  for (auto [from, to] : {std::pair{&state.m, &m_}, std::pair{&state.v, &v_}}) {
    to->means.Upload(from->means);
    to->log_scales.Upload(from->log_scales);
    to->quats.Upload(from->quats);
    to->opacity_logits.Upload(from->opacity_logits);
    to->sh.Upload(from->sh);
    to->dynamic_logits.Upload(from->dynamic_logits);
  }
}

}  // namespace cuda
}  // namespace es
