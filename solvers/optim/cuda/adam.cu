// Adam on the device, one thread per value: AdamStep::Update's
// AdamValueUpdate (solvers/optim/adam_value.h) in double.

#include "core/base/cuda/cuda_check.h"
#include "solvers/optim/cuda/adam_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

__global__ void AdamKernel(long long n, int period, int head,
                           AdamKernelStep head_step, AdamKernelStep tail_step,
                           const double* grad, double* m, double* v,
                           double* x) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i >= n) return;
  const AdamKernelStep& s = i % period < head ? head_step : tail_step;
  if (!s.on) return;
  AdamValueUpdate(s.constants, grad[i], &m[i], &v[i], &x[i]);
}

}  // namespace

void AdamUpdateKernel(long long n, int period, int head,
                      const AdamKernelStep& head_step,
                      const AdamKernelStep& tail_step, const double* grad,
                      double* m, double* v, double* x) {
  if (n == 0) return;
  const int blocks = static_cast<int>((n + kThreads - 1) / kThreads);
  AdamKernel<<<blocks, kThreads>>>(n, period, head, head_step, tail_step,
                                   grad, m, v, x);
  ES_CUDA_CHECK_LAUNCH("AdamKernel");
}

}  // namespace cuda
}  // namespace es
