// Adam on the device, one thread per value, with AdamStep::Update's
// arithmetic (solvers/optim/adam.h) in double.

#include "core/base/cuda/cuda_check.h"
#include "solvers/optim/cuda/adam_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

__global__ void AdamKernel(long long n, int period, int head,
                           AdamConstants head_step, AdamConstants tail_step,
                           const double* grad, double* m, double* v,
                           double* x) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i >= n) return;
  const AdamConstants& c = i % period < head ? head_step : tail_step;
  if (!c.on) return;
  const double g = grad[i];
  const double mi = c.beta1 * m[i] + (1.0 - c.beta1) * g;
  const double vi = c.beta2 * v[i] + (1.0 - c.beta2) * g * g;
  m[i] = mi;
  v[i] = vi;
  x[i] -= c.step * mi / (sqrt(vi) * c.inv_sqrt_bc2 + c.eps);
}

}  // namespace

void AdamUpdateKernel(long long n, int period, int head,
                      const AdamConstants& head_step,
                      const AdamConstants& tail_step, const double* grad,
                      double* m, double* v, double* x) {
  if (n == 0) return;
  const int blocks = static_cast<int>((n + kThreads - 1) / kThreads);
  AdamKernel<<<blocks, kThreads>>>(n, period, head, head_step, tail_step,
                                   grad, m, v, x);
  ES_CUDA_CHECK_LAUNCH("AdamKernel");
}

}  // namespace cuda
}  // namespace es
