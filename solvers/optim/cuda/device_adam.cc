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
AdamKernelStep Constants(const AdamOptions& options, int64_t t, double lr) {
  AdamKernelStep s;
  s.on = lr != 0;
  if (s.on) s.constants = AdamStep(options, t, lr);
  return s;
}

}  // namespace

void DeviceAdamUpdate(const AdamOptions& options, int64_t t, double lr,
                      int n, const double* grad, double* m, double* v,
                      double* x) {
  const AdamKernelStep c = Constants(options, t, lr);
  AdamUpdateKernel(n, 1, 1, c, c, grad, m, v, x);
}

void DeviceGaussianAdam::Reset(int count, int sh_degree) {
  count_ = count;
  sh_degree_ = sh_degree;
  for (Moments* moments : {&m_, &v_}) {
    for (int k = 0; k < kNumGaussianArrays; ++k) {
      DeviceBuffer<double>& b = (*moments)[k];
      b.Resize(static_cast<size_t>(
                   kGaussianArrays[k].Width(NumShCoeffs(sh_degree))) *
               count);
      b.Zero();
    }
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
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    const long long size = m_[k].size();
    if (size == 0) continue;
    const AdamKernelStep rate =
        Constants(options_, step_, lr.*kArrayLearningRates[k]);
    // SH: per Gaussian 3 DC values (rate), then the higher bands.
    const bool sh = k == kShArray;
    AdamUpdateKernel(size, sh ? 3 * NumShCoeffs(sh_degree_) : 1, sh ? 3 : 1,
                     rate, sh ? Constants(options_, step_, lr.sh_rest) : rate,
                     grad.arrays[k], m_[k].data(), v_[k].data(),
                     params.arrays[k]);
  }
}

void DeviceGaussianAdam::Download(GaussianSet* m, GaussianSet* v) const {
  for (auto [from, to] : {std::pair{&m_, m}, std::pair{&v_, v}}) {
    to->sh_degree = sh_degree_;
    for (int k = 0; k < kNumGaussianArrays; ++k)
      to->*kGaussianArrays[k].values = (*from)[k].Download();
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
  for (auto [from, to] : {std::pair{&state.m, &m_}, std::pair{&state.v, &v_}})
    for (int k = 0; k < kNumGaussianArrays; ++k)
      (*to)[k].Upload(from->*kGaussianArrays[k].values);
}

}  // namespace cuda
}  // namespace es
