// The device render costs' element-wise kernels (splat_cost_kernels.h),
// with the CPU costs' arithmetic in double.

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "costs/cuda/splat_cost_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

__global__ void SigmoidKernel(int n, const double* logits,
                              double* probability) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) probability[i] = 1.0 / (1.0 + exp(-logits[i]));
}

__global__ void LogitGradientKernel(int n, const double* d_probability,
                                    const double* probability, double scale,
                                    bool add, double* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double p = probability[i];
  const double g = d_probability[i] * p * (1 - p) * scale;
  out[i] = add ? out[i] + g : g;
}

__global__ void AddFloatKernel(long long n, const float* from, float* to) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < n) to[i] += from[i];
}

__global__ void ScaleKernel(long long n, double scale, double* x) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < n) x[i] *= scale;
}

__global__ void AverageIntoKernel(long long n, const double* b, double* a) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < n) a[i] = 0.5 * (a[i] + b[i]);
}

}  // namespace

void SigmoidArray(int n, const double* logits, double* probability) {
  if (n == 0) return;
  SigmoidKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, logits, probability);
  ES_CUDA_CHECK_LAUNCH("SigmoidKernel");
}

void DynamicLogitGradient(int n, const double* d_probability,
                          const double* probability, double scale,
                          double* out) {
  if (n == 0) return;
  LogitGradientKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, d_probability, probability, scale, false, out);
  ES_CUDA_CHECK_LAUNCH("LogitGradientKernel");
}

void AddDynamicLogitGradient(int n, const double* d_probability,
                             const double* probability, double scale,
                             double* out) {
  if (n == 0) return;
  LogitGradientKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, d_probability, probability, scale, true, out);
  ES_CUDA_CHECK_LAUNCH("LogitGradientKernel");
}

void ScaleArray(long long n, double scale, double* x) {
  if (n == 0) return;
  ScaleKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, scale, x);
  ES_CUDA_CHECK_LAUNCH("ScaleKernel");
}

void AddFloatArray(long long n, const float* from, float* to) {
  if (n == 0) return;
  AddFloatKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, from, to);
  ES_CUDA_CHECK_LAUNCH("AddFloatKernel");
}

void AverageInto(long long n, const double* b, double* a) {
  if (n == 0) return;
  AverageIntoKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, b, a);
  ES_CUDA_CHECK_LAUNCH("AverageIntoKernel");
}

}  // namespace cuda
}  // namespace es
