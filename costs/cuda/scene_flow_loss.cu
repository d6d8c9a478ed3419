// The device scene-flow prior's own kernels: its batch gathered from the
// uploaded samples, and V's residual against the lifted velocities.

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "costs/cuda/scene_flow_loss_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

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

// Row s of d: P_s (d_s - target_s), without the subtraction where target is
// null.
__global__ void ProjectOutUnseenKernel(int n, const double* target,
                                       const double* unseen, double* d) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= n) return;
  const double* u = unseen + 3LL * s;
  double* r = d + 3LL * s;
  if (target != nullptr) {
    for (int c = 0; c < 3; ++c) r[c] -= target[3LL * s + c];
  }
  const double along = r[0] * u[0] + r[1] * u[1] + r[2] * u[2];
  for (int c = 0; c < 3; ++c) r[c] -= along * u[c];
}

}  // namespace

void GatherSceneFlowBatch(int n, const int* indices, const double* samples_x,
                          const double* samples_v,
                          const double* samples_unseen, double* x,
                          double* target, double* unseen) {
  GatherKernel<<<GridBlocks(3LL * n, kThreads), kThreads>>>(
      n, indices, samples_x, samples_v, samples_unseen, x, target, unseen);
  ES_CUDA_CHECK_LAUNCH("GatherKernel");
}

void ConstrainedDifference(int n, const double* target,
                           const double* unseen, double* v) {
  ProjectOutUnseenKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, target,
                                                                unseen, v);
  ES_CUDA_CHECK_LAUNCH("ProjectOutUnseenKernel");
}

void ProjectOutUnseen(int n, const double* unseen, double* d) {
  ProjectOutUnseenKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, nullptr,
                                                                unseen, d);
  ES_CUDA_CHECK_LAUNCH("ProjectOutUnseenKernel");
}

}  // namespace cuda
}  // namespace es
