// The device scene-flow prior's own kernels: its batch gathered from the
// uploaded samples, and V's residual against the lifted velocities.

#include "core/render/cuda/cuda_check.h"
#include "solvers/train/cuda/flow_prior_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

int Blocks(long long count) {
  return static_cast<int>((count + kThreads - 1) / kThreads);
}

__global__ void GatherKernel(int n, const int* indices,
                             const double* samples_x,
                             const double* samples_v,
                             const double* samples_unseen, double* x,
                             double* target, double* unseen) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i >= 3LL * n) return;
  const long long from = 3LL * indices[i / 3] + i % 3;
  x[i] = samples_x[from];
  target[i] = samples_v[from];
  unseen[i] = samples_unseen[from];
}

__global__ void SubtractKernel(long long n, const double* target,
                               double* v) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < n) v[i] -= target[i];
}

__global__ void ProjectOutUnseenKernel(int n, const double* unseen,
                                       double* d) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  const double* u = unseen + 3LL * s;
  double* r = d + 3LL * s;
  const double along = r[0] * u[0] + r[1] * u[1] + r[2] * u[2];
  for (int c = 0; c < 3; ++c) r[c] -= along * u[c];
}

}  // namespace

void GatherSceneFlowBatch(int n, const int* indices, const double* samples_x,
                          const double* samples_v,
                          const double* samples_unseen, double* x,
                          double* target, double* unseen) {
  GatherKernel<<<Blocks(3LL * n), kThreads>>>(n, indices, samples_x,
                                              samples_v, samples_unseen, x,
                                              target, unseen);
  ES_CUDA_CHECK_LAUNCH("GatherKernel");
}

void SubtractTarget(long long n, const double* target, double* v) {
  SubtractKernel<<<Blocks(n), kThreads>>>(n, target, v);
  ES_CUDA_CHECK_LAUNCH("SubtractKernel");
}

void ProjectOutUnseen(int n, const double* unseen, double* d) {
  ProjectOutUnseenKernel<<<Blocks(n), kThreads>>>(n, unseen, d);
  ES_CUDA_CHECK_LAUNCH("ProjectOutUnseenKernel");
}

}  // namespace cuda
}  // namespace es
