// The photometric loss's kernels on the device: SSIM's separable window
// passes and per-value terms in float, with the formulas and evaluation
// order of core/metrics/ssim_kernels_impl.h (SsimRow, BlurRow,
// BlurColumn), and L1. Sums go through per-block partials added in block
// order, so the loss does not depend on the order blocks finish in.

#include "core/metrics/ssim_kernels.h"
#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "costs/cuda/photometric_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;
constexpr float kC1 = static_cast<float>(kSsimC1);
constexpr float kC2 = static_cast<float>(kSsimC2);

// Block b's sums of a and b into partials[2 b], [2 b + 1] (a tree over
// shared memory; every thread of the block calls it).
__device__ void BlockSums(double a, double b, double* partials) {
  __shared__ double sa[kThreads];
  __shared__ double sb[kThreads];
  const int t = threadIdx.x;
  sa[t] = a;
  sb[t] = b;
  __syncthreads();
  for (int half = kThreads / 2; half > 0; half /= 2) {
    if (t < half) {
      sa[t] += sa[t + half];
      sb[t] += sb[t + half];
    }
    __syncthreads();
  }
  if (t == 0) {
    partials[2 * blockIdx.x] = sa[0];
    partials[2 * blockIdx.x + 1] = sb[0];
  }
}

__global__ void ProductsKernel(long long n, const float* x, const float* y,
                               float* planes) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i >= n) return;
  const float v = x[i], u = y[i];
  planes[i] = v;
  planes[n + i] = v * v;
  planes[2 * n + i] = v * u;
  planes[3 * n + i] = u;
  planes[4 * n + i] = u * u;
}

// Value j of a row (or column), zero outside [0, len): `stride` apart.
__device__ inline float Tap(const float* p, int j, int len, int stride) {
  return j >= 0 && j < len ? p[static_cast<long long>(j) * stride] : 0.0f;
}

// BlurRow: neighbours `channels` apart along a row.
__global__ void BlurRowsKernel(int count, int rows, int row_len,
                               int channels, SsimWindow win,
                               const float* planes, float* out) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  const long long n = static_cast<long long>(rows) * row_len;
  if (i >= count * n) return;
  const int j = static_cast<int>(i % row_len);
  const float* p = planes + (i - j);  // the row's start
  const int c = channels;
  const float* w = win.w;
  out[i] = w[0] * p[j] +
           w[1] * (Tap(p, j - c, row_len, 1) + Tap(p, j + c, row_len, 1)) +
           w[2] * (Tap(p, j - 2 * c, row_len, 1) +
                   Tap(p, j + 2 * c, row_len, 1)) +
           w[3] * (Tap(p, j - 3 * c, row_len, 1) +
                   Tap(p, j + 3 * c, row_len, 1)) +
           w[4] * (Tap(p, j - 4 * c, row_len, 1) +
                   Tap(p, j + 4 * c, row_len, 1)) +
           w[5] * (Tap(p, j - 5 * c, row_len, 1) +
                   Tap(p, j + 5 * c, row_len, 1));
}

// BlurColumn: rows outside the image are zeros.
__global__ void BlurColumnsKernel(int count, int rows, int row_len,
                                  SsimWindow win, const float* planes,
                                  float* out) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  const long long n = static_cast<long long>(rows) * row_len;
  if (i >= count * n) return;
  const long long k = i / n;
  const int r = static_cast<int>(i % n / row_len);
  const int j = static_cast<int>(i % row_len);
  const float* p = planes + k * n + j;  // the column's top
  const float* w = win.w;
  out[i] = w[0] * p[static_cast<long long>(r) * row_len] +
           w[1] * (Tap(p, r - 1, rows, row_len) +
                   Tap(p, r + 1, rows, row_len)) +
           w[2] * (Tap(p, r - 2, rows, row_len) +
                   Tap(p, r + 2, rows, row_len)) +
           w[3] * (Tap(p, r - 3, rows, row_len) +
                   Tap(p, r + 3, rows, row_len)) +
           w[4] * (Tap(p, r - 4, rows, row_len) +
                   Tap(p, r + 4, rows, row_len)) +
           w[5] * (Tap(p, r - 5, rows, row_len) +
                   Tap(p, r + 5, rows, row_len));
}

// SsimRow, value by value (and TargetStats' var = G y^2 - mu^2).
__global__ void SsimTermsKernel(long long n, const float* blurred,
                                const float* x, const float* y,
                                float* terms, double* partials) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  double s_sum = 0, l1_sum = 0;
  if (i < n) {
    const float inv_count = static_cast<float>(1.0 / static_cast<double>(n));
    const float mx = blurred[i], my = blurred[3 * n + i];
    const float var_y = blurred[4 * n + i] - my * my;
    const float sxx = blurred[n + i] - mx * mx;
    const float sxy = blurred[2 * n + i] - mx * my;
    const float a1 = 2 * mx * my + kC1, a2 = 2 * sxy + kC2;
    const float b1 = mx * mx + my * my + kC1, b2 = sxx + var_y + kC2;
    const float inv = 1 / (b1 * b2);
    const float s = a1 * a2 * inv;
    if (terms != nullptr) {
      const float ds_dsxx = -s * b1 * inv;
      const float ds_dsxy = 2 * a1 * inv;
      const float ds_dmx = 2 * my * a2 * inv - 2 * mx * s * b2 * inv;
      terms[i] = (ds_dmx - 2 * mx * ds_dsxx - my * ds_dsxy) * inv_count;
      terms[n + i] = ds_dsxx * inv_count;
      terms[2 * n + i] = ds_dsxy * inv_count;
    }
    s_sum = s;
    l1_sum = fabsf(x[i] - y[i]);
  }
  BlockSums(s_sum, l1_sum, partials);
}

__device__ inline float Sign(float v, float u) {
  return static_cast<float>(v > u) - static_cast<float>(v < u);
}

__global__ void SsimGradientKernel(long long n, const float* g,
                                   const float* x, const float* y,
                                   double ssim_scale, double l1_scale,
                                   float* d) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i >= n) return;
  const float v = x[i], u = y[i];
  d[i] = static_cast<float>(
      ssim_scale *
          static_cast<double>(g[i] + 2 * v * g[n + i] + u * g[2 * n + i]) +
      l1_scale * static_cast<double>(Sign(v, u)));
}

__global__ void L1Kernel(long long n, const float* x, const float* y,
                         double l1_scale, float* d, double* partials) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  double sum = 0;
  if (i < n) {
    // The CPU's L1 without SSIM differences in double.
    const double diff = static_cast<double>(x[i]) - y[i];
    sum = fabs(diff);
    if (d != nullptr)
      d[i] = static_cast<float>(l1_scale * ((diff > 0) - (diff < 0)));
  }
  BlockSums(0.0, sum, partials);
}

__global__ void SumPartialsKernel(int blocks, const double* partials,
                                  double* sums) {
  double a = 0, b = 0;
  for (int k = 0; k < blocks; ++k) {
    a += partials[2 * k];
    b += partials[2 * k + 1];
  }
  sums[0] = a;
  sums[1] = b;
}

}  // namespace

int PhotometricBlocks(long long n) { return GridBlocks(n, kThreads); }

void SsimProducts(long long n, const float* x, const float* y,
                  float* planes) {
  ProductsKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, x, y, planes);
  ES_CUDA_CHECK_LAUNCH("ProductsKernel");
}

void SsimBlur(int count, int rows, int row_len, int channels,
              const SsimWindow& window, const float* planes, float* scratch,
              float* out) {
  const long long values = static_cast<long long>(count) * rows * row_len;
  BlurRowsKernel<<<GridBlocks(values, kThreads), kThreads>>>(
      count, rows, row_len, channels, window, planes, scratch);
  ES_CUDA_CHECK_LAUNCH("BlurRowsKernel");
  BlurColumnsKernel<<<GridBlocks(values, kThreads), kThreads>>>(
      count, rows, row_len, window, scratch, out);
  ES_CUDA_CHECK_LAUNCH("BlurColumnsKernel");
}

void SsimTerms(long long n, const float* blurred, const float* x,
               const float* y, float* terms, double* partials) {
  SsimTermsKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, blurred, x, y,
                                                         terms, partials);
  ES_CUDA_CHECK_LAUNCH("SsimTermsKernel");
}

void SsimGradient(long long n, const float* blurred_terms, const float* x,
                  const float* y, double ssim_scale, double l1_scale,
                  float* d) {
  SsimGradientKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, blurred_terms, x, y, ssim_scale, l1_scale, d);
  ES_CUDA_CHECK_LAUNCH("SsimGradientKernel");
}

void L1Terms(long long n, const float* x, const float* y, double l1_scale,
             float* d, double* partials) {
  L1Kernel<<<GridBlocks(n, kThreads), kThreads>>>(n, x, y, l1_scale, d,
                                                  partials);
  ES_CUDA_CHECK_LAUNCH("L1Kernel");
}

void SumPartials(int blocks, const double* partials, double* sums) {
  SumPartialsKernel<<<1, 1>>>(blocks, partials, sums);
  ES_CUDA_CHECK_LAUNCH("SumPartialsKernel");
}

}  // namespace cuda
}  // namespace es
