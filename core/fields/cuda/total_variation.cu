// Triplane::TotalVariation (core/fields/triplane.cc) on the device. The CPU
// scatters each neighbour pair's gradient to both texels; here each thread
// gathers its own value's from its four neighbours, so there are no atomics.
// The sum goes through per-block partials added in block order, so the
// value does not depend on the order blocks finish in.

#include "core/fields/cuda/field_kernels.h"
#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

__global__ void TermsKernel(int r, int c, const double* params,
                            double grad_scale, double* d_params,
                            double* partials) {
  const long long i = GridIndex();
  const long long n = 3LL * r * r * c;
  double square = 0;
  if (i < n) {
    // params[((plane r + row) r + col) c + k].
    const long long texel = i / c;
    const int col = static_cast<int>(texel % r);
    const int row = static_cast<int>(texel / r % r);
    const long long right = c, down = static_cast<long long>(r) * c;
    const double p = params[i];
    double d = 0;  // d (sum of squares) / d params[i]
    if (col + 1 < r) {
      const double diff = params[i + right] - p;
      square += diff * diff;
      d -= 2 * diff;
    }
    if (row + 1 < r) {
      const double diff = params[i + down] - p;
      square += diff * diff;
      d -= 2 * diff;
    }
    if (col > 0) d += 2 * (p - params[i - right]);
    if (row > 0) d += 2 * (p - params[i - down]);
    if (d_params != nullptr) d_params[i] += grad_scale * d;
  }
  BlockSum<kThreads>(square, partials);
}

__global__ void SumKernel(int blocks, const double* partials, double* sum) {
  double total = 0;
  for (int b = 0; b < blocks; ++b) total += partials[b];
  sum[0] = total;
}

}  // namespace

int TotalVariationBlocks(long long num_params) {
  return GridBlocks(num_params, kThreads);
}

void TotalVariationKernel(int resolution, int channels, const double* params,
                          double grad_scale, double* d_params,
                          double* partials) {
  const long long n = 3LL * resolution * resolution * channels;
  TermsKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      resolution, channels, params, grad_scale, d_params, partials);
  ES_CUDA_CHECK_LAUNCH("TotalVariationTermsKernel");
}

void SumTotalVariationPartials(int blocks, const double* partials,
                               double* sum) {
  SumKernel<<<1, 1>>>(blocks, partials, sum);
  ES_CUDA_CHECK_LAUNCH("TotalVariationSumKernel");
}

}  // namespace cuda
}  // namespace es
