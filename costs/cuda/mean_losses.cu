// The mask BCE and residual L2 losses' kernels on the device: per value
// the terms of MaskBceMean (costs/mask_bce_terms.h) and ResidualL2Mean
// (costs/residual_l2_terms.h) in double, with the same clamps and
// gradients. Sums go through per-block partials added in block order, so
// a loss does not depend on the order blocks finish in.

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "costs/cuda/mean_loss_kernels.h"
#include "costs/mask_bce_terms.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

__global__ void MaskBceKernel(long long n, const float* extra, int num_extra,
                              int channel, const float* mask,
                              double grad_scale, float* d_extra,
                              double* partials) {
  const long long i = GridIndex();
  double term = 0;
  if (i < n) {
    const long long at = i * num_extra + channel;
    const double raw = extra[at];
    // std::min(std::max(raw, lo), hi), NaN included.
    const double lo = kMaskProbabilityMargin, hi = 1.0 - lo;
    const double at_least_lo = raw < lo ? lo : raw;
    const double p = hi < at_least_lo ? hi : at_least_lo;
    const double t = mask[i];
    // MaskBceMean's branches: one logarithm for a 0 or 1 mask value.
    if (t == 0) {
      term = -log(1 - p);
    } else if (t == 1) {
      term = -log(p);
    } else {
      term = -(t * log(p) + (1 - t) * log(1 - p));
    }
    if (d_extra != nullptr) {
      d_extra[at] = static_cast<float>(
          p == raw ? grad_scale * ((1 - t) / (1 - p) - t / p) : 0.0);
    }
  }
  BlockSum<kThreads>(term, partials);
}

__global__ void ResidualL2Kernel(long long n, const double* residuals,
                                 double grad_scale, double* d,
                                 double* partials) {
  const long long i = GridIndex();
  double square = 0;
  if (i < n) {
    const double r = residuals[i];
    square = r * r;
    if (d != nullptr) d[i] = grad_scale * r;
  }
  BlockSum<kThreads>(square, partials);
}

__global__ void SumPartialsKernel(int blocks, const double* partials,
                                  double* sum) {
  double s = 0;
  for (int k = 0; k < blocks; ++k) s += partials[k];
  sum[0] = s;
}

}  // namespace

int MeanLossBlocks(long long n) { return GridBlocks(n, kThreads); }

void MaskBceTerms(long long n, const float* extra, int num_extra,
                  int channel, const float* mask, double grad_scale,
                  float* d_extra, double* partials) {
  MaskBceKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, extra, num_extra, channel, mask, grad_scale, d_extra, partials);
  ES_CUDA_CHECK_LAUNCH("MaskBceKernel");
}

void ResidualL2Terms(long long n, const double* residuals, double grad_scale,
                     double* d, double* partials) {
  ResidualL2Kernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, residuals, grad_scale, d, partials);
  ES_CUDA_CHECK_LAUNCH("ResidualL2Kernel");
}

void SumMeanLossPartials(int blocks, const double* partials, double* sum) {
  SumPartialsKernel<<<1, 1>>>(blocks, partials, sum);
  ES_CUDA_CHECK_LAUNCH("SumPartialsKernel");
}

}  // namespace cuda
}  // namespace es
