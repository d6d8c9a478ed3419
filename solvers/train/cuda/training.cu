// The device trainer's kernels (training_kernels.h): the densification
// statistics in DensityStats::AddView's arithmetic, and the finiteness
// check of the divergence guard.

#include "core/render/cuda/cuda_check.h"
#include "solvers/train/cuda/training_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

int Blocks(long long n) {
  return static_cast<int>((n + kThreads - 1) / kThreads);
}

__global__ void AddViewKernel(int count, double half_w, double half_h,
                              const int* radii, const double* mean2d_grads,
                              double* grad_sum, double* views,
                              double* max_radius) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count || radii[i] <= 0) return;
  grad_sum[i] += hypot(mean2d_grads[2 * i] * half_w,
                       mean2d_grads[2 * i + 1] * half_h);
  views[i] += 1;
  const double r = radii[i];
  max_radius[i] = max_radius[i] < r ? r : max_radius[i];
}

__global__ void NonFiniteKernel(long long n, const double* x, int* flag) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  // x - x is 0 for finite x and NaN for NaN and infinities.
  if (i < n && !(x[i] - x[i] == 0.0)) atomicMax(flag, 1);
}

}  // namespace

void AddViewStats(int count, double half_w, double half_h, const int* radii,
                  const double* mean2d_grads, double* grad_sum,
                  double* views, double* max_radius) {
  if (count == 0) return;
  AddViewKernel<<<Blocks(count), kThreads>>>(count, half_w, half_h, radii,
                                             mean2d_grads, grad_sum, views,
                                             max_radius);
  ES_CUDA_CHECK_LAUNCH("AddViewKernel");
}

void FlagNonFinite(long long n, const double* x, int* flag) {
  if (n == 0) return;
  NonFiniteKernel<<<Blocks(n), kThreads>>>(n, x, flag);
  ES_CUDA_CHECK_LAUNCH("NonFiniteKernel");
}

}  // namespace cuda
}  // namespace es
