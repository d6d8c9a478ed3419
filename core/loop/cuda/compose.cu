// A looping frame's splats on the device: FrameComposer's assembly and
// its backward (core/loop/frame_composer.cc), one thread per Gaussian, the
// same additions in double.

#include "core/loop/cuda/compose_kernels.h"
#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 128;

__global__ void ComposeKernel(int m, const int* dynamic,
                              const double* positions,
                              const double* residuals, ResidualLayout layout,
                              int coeffs, int offset_coeffs, double* means,
                              double* opacity_logits, double* sh) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  const long long n = dynamic[k];
  double* mean = means + 3 * n;
  for (int j = 0; j < 3; ++j) mean[j] = positions[3LL * k + j];
  if (residuals == nullptr) return;
  const double* d = residuals + static_cast<long long>(k) * layout.dim;
  for (int j = 0; j < 3; ++j) mean[j] += d[layout.position + j];
  opacity_logits[n] += d[layout.opacity];
  double* s = sh + 3 * n * coeffs;
  for (int i = 0; i < 3 * offset_coeffs; ++i) s[i] += d[layout.sh + i];
}

__global__ void GatherMeansKernel(int m, const int* dynamic,
                                  const double* means, double* x0) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  const long long n = dynamic[k];
  for (int j = 0; j < 3; ++j) x0[3LL * k + j] = means[3 * n + j];
}

__global__ void BackwardKernel(int m, const int* dynamic,
                               const double* d_means, const double* d_opacity,
                               const double* d_sh, ResidualLayout layout,
                               int coeffs, int offset_coeffs,
                               const double* extra_d_residuals,
                               double* d_positions, double* d_residuals) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  const long long n = dynamic[k];
  const double* d_mean = d_means + 3 * n;
  for (int j = 0; j < 3; ++j) d_positions[3LL * k + j] = d_mean[j];
  if (d_residuals == nullptr) return;
  const long long row = static_cast<long long>(k) * layout.dim;
  double* d = d_residuals + row;
  for (int i = 0; i < layout.dim; ++i) d[i] = 0.0;
  for (int j = 0; j < 3; ++j) d[layout.position + j] = d_mean[j];
  d[layout.opacity] = d_opacity[n];
  const double* g = d_sh + 3 * n * coeffs;
  for (int i = 0; i < 3 * offset_coeffs; ++i) d[layout.sh + i] = g[i];
  if (extra_d_residuals == nullptr) return;
  const double* extra = extra_d_residuals + row;
  for (int i = 0; i < layout.dim; ++i) d[i] += extra[i];
}

__global__ void MeansGradientKernel(int count, const int* slot,
                                    const double* d_means, const double* d_x0,
                                    double* out) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const int k = slot[n];
  const double* from = k < 0 ? d_means + 3LL * n : d_x0 + 3LL * k;
  for (int j = 0; j < 3; ++j) out[3LL * n + j] += from[j];
}

__global__ void AddKernel(long long count, const double* from, double* to) {
  const long long i =
      static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < count) to[i] += from[i];
}

}  // namespace

void ComposeDynamicKernel(int m, const int* dynamic, const double* positions,
                          const double* residuals,
                          const ResidualLayout& layout, int coeffs,
                          int offset_coeffs, double* means,
                          double* opacity_logits, double* sh) {
  if (m == 0) return;
  ComposeKernel<<<GridBlocks(m, kThreads), kThreads>>>(
      m, dynamic, positions, residuals, layout, coeffs, offset_coeffs, means,
      opacity_logits, sh);
  ES_CUDA_CHECK_LAUNCH("ComposeDynamicKernel");
}

void GatherDynamicMeansKernel(int m, const int* dynamic, const double* means,
                              double* x0) {
  if (m == 0) return;
  GatherMeansKernel<<<GridBlocks(m, kThreads), kThreads>>>(m, dynamic, means,
                                                           x0);
  ES_CUDA_CHECK_LAUNCH("GatherDynamicMeansKernel");
}

void ComposeBackwardKernel(int m, const int* dynamic, const double* d_means,
                           const double* d_opacity, const double* d_sh,
                           const ResidualLayout& layout, int coeffs,
                           int offset_coeffs, const double* extra_d_residuals,
                           double* d_positions, double* d_residuals) {
  if (m == 0) return;
  BackwardKernel<<<GridBlocks(m, kThreads), kThreads>>>(
      m, dynamic, d_means, d_opacity, d_sh, layout, coeffs, offset_coeffs,
      extra_d_residuals, d_positions, d_residuals);
  ES_CUDA_CHECK_LAUNCH("ComposeBackwardKernel");
}

void AddMeansGradientKernel(int count, const int* slot, const double* d_means,
                            const double* d_x0, double* out) {
  if (count == 0) return;
  MeansGradientKernel<<<GridBlocks(count, kThreads), kThreads>>>(
      count, slot, d_means, d_x0, out);
  ES_CUDA_CHECK_LAUNCH("AddMeansGradientKernel");
}

void AddDoublesKernel(long long count, const double* from, double* to) {
  if (count == 0) return;
  AddKernel<<<GridBlocks(count, kThreads), kThreads>>>(count, from, to);
  ES_CUDA_CHECK_LAUNCH("AddDoublesKernel");
}

}  // namespace cuda
}  // namespace es
