// The device trainer's kernels (training_kernels.h): the densification
// statistics in DensityStats::AddView's arithmetic, the finiteness check
// of the divergence guard and the water's scale bound.

#include <cmath>
#include <cstring>
#include <limits>

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "solvers/train/cuda/training_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

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

// A grid-stride maximum per thread, a tree in shared memory per block and
// one atomicMax per block.
__global__ void MaxMagnitudeBitsKernel(long long n, const double* x,
                                       unsigned long long* max_bits) {
  __shared__ unsigned long long best[kThreads];
  unsigned long long mine = 0;
  const long long stride = static_cast<long long>(gridDim.x) * blockDim.x;
  for (long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                     threadIdx.x;
       i < n; i += stride) {
    const unsigned long long bits =
        static_cast<unsigned long long>(__double_as_longlong(fabs(x[i])));
    mine = bits > mine ? bits : mine;
  }
  best[threadIdx.x] = mine;
  __syncthreads();
  for (int s = blockDim.x / 2; s > 0; s >>= 1) {
    if (threadIdx.x < s && best[threadIdx.x + s] > best[threadIdx.x])
      best[threadIdx.x] = best[threadIdx.x + s];
    __syncthreads();
  }
  if (threadIdx.x == 0) atomicMax(max_bits, best[0]);
}

__global__ void ClampLogScalesKernel(int m, const int* dynamic,
                                     const double* max_log_scale,
                                     double* log_scales) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  double* s = log_scales + 3 * static_cast<long long>(dynamic[k]);
  for (int a = 0; a < 3; ++a)
    if (s[a] > max_log_scale[k]) s[a] = max_log_scale[k];
}

}  // namespace

void AddViewStats(int count, double half_w, double half_h, const int* radii,
                  const double* mean2d_grads, double* grad_sum,
                  double* views, double* max_radius) {
  if (count == 0) return;
  AddViewKernel<<<GridBlocks(count, kThreads), kThreads>>>(
      count, half_w, half_h, radii, mean2d_grads, grad_sum, views, max_radius);
  ES_CUDA_CHECK_LAUNCH("AddViewKernel");
}

void FlagNonFinite(long long n, const double* x, int* flag) {
  if (n == 0) return;
  NonFiniteKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, x, flag);
  ES_CUDA_CHECK_LAUNCH("NonFiniteKernel");
}

void RaiseMaxMagnitudeBits(long long n, const double* x,
                           unsigned long long* max_bits) {
  if (n == 0) return;
  const int blocks =
      GridBlocks(n, kThreads) < 1024 ? GridBlocks(n, kThreads) : 1024;
  MaxMagnitudeBitsKernel<<<blocks, kThreads>>>(n, x, max_bits);
  ES_CUDA_CHECK_LAUNCH("MaxMagnitudeBitsKernel");
}

double MagnitudeOfBits(unsigned long long bits) {
  double value;
  std::memcpy(&value, &bits, sizeof(value));
  return std::isnan(value) ? std::numeric_limits<double>::infinity() : value;
}

void ClampLogScales(int m, const int* dynamic, const double* max_log_scale,
                    double* log_scales) {
  if (m == 0) return;
  ClampLogScalesKernel<<<GridBlocks(m, kThreads), kThreads>>>(
      m, dynamic, max_log_scale, log_scales);
  ES_CUDA_CHECK_LAUNCH("ClampLogScalesKernel");
}

}  // namespace cuda
}  // namespace es
