// A looping frame's splats on the device: FrameComposer's assembly
// (core/loop/frame_composer.cc), one thread per dynamic Gaussian, the same
// additions in double.

#include "core/loop/cuda/compose_kernels.h"
#include "core/render/cuda/cuda_check.h"

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

}  // namespace

void ComposeDynamicKernel(int m, const int* dynamic, const double* positions,
                          const double* residuals,
                          const ResidualLayout& layout, int coeffs,
                          int offset_coeffs, double* means,
                          double* opacity_logits, double* sh) {
  if (m == 0) return;
  ComposeKernel<<<(m + kThreads - 1) / kThreads, kThreads>>>(
      m, dynamic, positions, residuals, layout, coeffs, offset_coeffs, means,
      opacity_logits, sh);
  ES_CUDA_CHECK_LAUNCH("ComposeDynamicKernel");
}

}  // namespace cuda
}  // namespace es
