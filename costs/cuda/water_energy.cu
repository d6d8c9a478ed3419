// The water energy loss's kernels on the device, in double like the CPU
// loss (costs/water_energy_loss.cc): opponent channels, separable
// Gaussian blurs with clamped borders and their adjoints, the amplitude
// L1 and the chain rule back to RGB, one thread per value. The adjoints
// gather where the CPU scatters: an inner value takes the taps that read
// it, a border value every (value, tap) pair that the clamp sends to it.
// Sums go through per-block partials added in block order, so the loss
// does not depend on the order blocks finish in.

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "costs/cuda/water_energy_kernels.h"

namespace es {
namespace cuda {
namespace {

// Small blocks: most passes are light, and a small image still fills
// many of them.
constexpr int kThreads = 128;

__device__ inline int Clamp(int i, int n) {
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// Blocks of `planes` planes of `pixels` values: block b is plane b /
// blocks, and this thread's pixel in it is PlanePixel(blocks).
__device__ inline long long PlanePixel(int blocks) {
  return static_cast<long long>(blockIdx.x % blocks) * kThreads + threadIdx.x;
}

__global__ void WaterKernel(long long pixels, int blocks, const float* mask_a,
                            const float* mask_b, double* water,
                            double* partials) {
  const int plane = blockIdx.x / blocks;
  const long long p = PlanePixel(blocks);
  double v = 0;
  if (p < pixels) {
    const bool a = mask_a == nullptr || mask_a[p] > 0.5f;
    const bool b = mask_b == nullptr || mask_b[p] > 0.5f;
    v = (plane == 0 ? a : (plane == 1 ? b : a || b)) ? 1.0 : 0.0;
    water[plane * pixels + p] = v;
  }
  BlockSum<kThreads>(v, partials);
}

__global__ void OpponentKernel(long long pixels, OpponentBasis basis,
                               const float* ra, const float* rb,
                               const float* ia, const float* ib, double* y) {
  const long long p = GridIndex();
  if (p >= pixels) return;
  const float* images[4] = {ra, rb, ia, ib};
  for (int f = 0; f < 4; ++f) {
    const float* v = images[f] + 3 * p;
    const double r = v[0], g = v[1], b = v[2];
    for (int c = 0; c < 3; ++c) {
      const double* k = basis.k[c];
      y[(3 * f + c) * pixels + p] = k[0] * r + k[1] * g + k[2] * b;
    }
  }
}

__global__ void MotionDifferencesKernel(long long pixels, const double* y,
                                        double* diff, double* square) {
  const long long i = GridIndex();
  if (i >= 6 * pixels) return;
  // Value i of [renders (3 planes) | inputs (3 planes)]: y's frame A of
  // the same kind is 3 planes further for inputs, B 3 planes after A.
  const long long a = i < 3 * pixels ? i : i + 3 * pixels;
  const double d = y[a + 3 * pixels] - y[a];
  diff[i] = d;
  square[i] = d * d;
}

__global__ void BlurRowsKernel(long long n, int width, const double* taps,
                               int radius, const double* in, double* out) {
  const long long i = GridIndex();
  if (i >= n) return;
  const int x = static_cast<int>(i % width);
  const double* row = in + (i - x);
  double sum = 0;
  for (int j = 0; j <= 2 * radius; ++j)
    sum += taps[j] * row[Clamp(x + j - radius, width)];
  out[i] = sum;
}

__global__ void BlurColumnsKernel(long long n, int width, int height,
                                  const double* taps, int radius,
                                  const double* in, double* out) {
  const long long i = GridIndex();
  if (i >= n) return;
  const int y = static_cast<int>(i / width % height);
  const double* column = in + (i - static_cast<long long>(y) * width);
  double sum = 0;
  for (int j = 0; j <= 2 * radius; ++j)
    sum += taps[j] * column[static_cast<long long>(Clamp(y + j - radius,
                                                         height)) * width];
  out[i] = sum;
}

// g_in[i] of a line of `len` values `stride` apart: the sum of taps[j]
// g_out[o] over every output o and tap j with clamp(o + j - radius) = i.
__device__ double GatherAdjoint(const double* line, int i, int len,
                                long long stride, const double* taps,
                                int radius) {
  double sum = 0;
  if (i > 0 && i < len - 1) {  // only unclamped reads reach it
    for (int j = 0; j <= 2 * radius; ++j) {
      const int o = i - j + radius;
      if (o >= 0 && o < len) sum += taps[j] * line[o * stride];
    }
    return sum;
  }
  const int lo = i - radius < 0 ? 0 : i - radius;
  const int hi = i + radius > len - 1 ? len - 1 : i + radius;
  for (int o = lo; o <= hi; ++o) {
    for (int j = 0; j <= 2 * radius; ++j) {
      if (Clamp(o + j - radius, len) == i) sum += taps[j] * line[o * stride];
    }
  }
  return sum;
}

__global__ void BlurRowsAdjointKernel(long long n, int width,
                                      const double* taps, int radius,
                                      const double* g_out, double* g_in) {
  const long long i = GridIndex();
  if (i >= n) return;
  const int x = static_cast<int>(i % width);
  g_in[i] = GatherAdjoint(g_out + (i - x), x, width, 1, taps, radius);
}

__global__ void BlurColumnsAdjointKernel(long long n, int width, int height,
                                         const double* taps, int radius,
                                         const double* g_out, double* g_in) {
  const long long i = GridIndex();
  if (i >= n) return;
  const int y = static_cast<int>(i / width % height);
  g_in[i] = GatherAdjoint(g_out + (i - static_cast<long long>(y) * width), y,
                          height, width, taps, radius);
}

__global__ void BandAndSquareKernel(long long n, const double* fine,
                                    const double* coarse, double* high,
                                    double* square) {
  const long long i = GridIndex();
  if (i >= n) return;
  const double h = fine[i] - coarse[i];
  high[i] = h;
  square[i] = h * h;
}

// WaterEnergyLoss::AmplitudeL1 per pixel; blocks as WaterKernel's.
__global__ void AmplitudeKernel(long long pixels, int blocks,
                                int planes_per_mask, const double* e_r,
                                const double* e_i, const double* water,
                                const double* counts,
                                ChannelFloors floors, double eps,
                                double scale, double* d_e,
                                double* partials) {
  const int plane = blockIdx.x / blocks;
  const long long p = PlanePixel(blocks);
  double term = 0;
  if (p < pixels) {
    const long long i = plane * pixels + p;
    const int mask = plane / planes_per_mask;
    double d = 0;
    if (water[mask * pixels + p] != 0) {
      const double a = sqrt(fmax(e_r[i], 0.0) + floors.c[plane % 3]);
      const double b = sqrt(fmax(e_i[i], 0.0) + eps);
      term = fabs(a - b);
      const double sign = a > b ? 1.0 : (a < b ? -1.0 : 0.0);
      d = scale * sign / (2 * a * counts[mask]);
    }
    if (d_e != nullptr) d_e[i] = d;
  }
  BlockSum<kThreads>(term, partials);
}

__global__ void AddMotionGradientKernel(long long pixels, const double* diff,
                                        const double* g, double* dy) {
  const long long i = GridIndex();
  if (i >= 3 * pixels) return;
  const double t = 2 * diff[i] * g[i];
  dy[3 * pixels + i] += t;
  dy[i] -= t;
}

__global__ void ScaleByTwiceKernel(long long n, const double* high,
                                   double* g) {
  const long long i = GridIndex();
  if (i < n) g[i] *= 2 * high[i];
}

__global__ void AddBandGradientKernel(long long n, const double* fine,
                                      const double* coarse, double* dy) {
  const long long i = GridIndex();
  if (i < n) dy[i] += fine[i] - coarse[i];
}

__global__ void AddRgbGradientsKernel(long long pixels, OpponentBasis basis,
                                      const double* dy, float* d_a,
                                      float* d_b) {
  const long long p = GridIndex();
  if (p >= pixels) return;
  float* out[2] = {d_a, d_b};
  for (int f = 0; f < 2; ++f) {
    if (out[f] == nullptr) continue;
    const double* d = dy + 3 * f * pixels + p;
    for (int j = 0; j < 3; ++j) {
      const double g = basis.k[0][j] * d[0] + basis.k[1][j] * d[pixels] +
                       basis.k[2][j] * d[2 * pixels];
      float* v = out[f] + 3 * p + j;
      *v = static_cast<float>(*v + g);
    }
  }
}

__global__ void SumSegmentsKernel(int segments, int blocks,
                                  const double* partials, double* sums) {
  const int s = static_cast<int>(GridIndex());
  if (s >= segments) return;
  double sum = 0;
  for (int b = 0; b < blocks; ++b)
    sum += partials[static_cast<long long>(s) * blocks + b];
  sums[s] = sum;
}

}  // namespace

int WaterEnergyBlocks(long long pixels) { return GridBlocks(pixels, kThreads); }

void WaterPlanes(long long pixels, const float* mask_a, const float* mask_b,
                 double* water, double* partials) {
  const int blocks = GridBlocks(pixels, kThreads);
  WaterKernel<<<3 * blocks, kThreads>>>(pixels, blocks, mask_a, mask_b,
                                        water, partials);
  ES_CUDA_CHECK_LAUNCH("WaterKernel");
}

void OpponentPlanes(long long pixels, const OpponentBasis& basis,
                    const float* rendered_a, const float* rendered_b,
                    const float* input_a, const float* input_b, double* y) {
  OpponentKernel<<<GridBlocks(pixels, kThreads), kThreads>>>(
      pixels, basis, rendered_a, rendered_b, input_a, input_b, y);
  ES_CUDA_CHECK_LAUNCH("OpponentKernel");
}

void MotionDifferences(long long pixels, const double* y, double* diff,
                       double* square) {
  MotionDifferencesKernel<<<GridBlocks(6 * pixels, kThreads), kThreads>>>(
      pixels, y, diff, square);
  ES_CUDA_CHECK_LAUNCH("MotionDifferencesKernel");
}

void ClampedBlur(int planes, int width, int height, const double* taps,
                 int radius, const double* in, double* scratch, double* out) {
  const long long n = static_cast<long long>(planes) * width * height;
  BlurRowsKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, width, taps, radius,
                                                        in, scratch);
  ES_CUDA_CHECK_LAUNCH("BlurRowsKernel");
  BlurColumnsKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, width, height, taps, radius, scratch, out);
  ES_CUDA_CHECK_LAUNCH("BlurColumnsKernel");
}

void ClampedBlurAdjoint(int planes, int width, int height,
                        const double* taps, int radius, const double* g_out,
                        double* scratch, double* g_in) {
  const long long n = static_cast<long long>(planes) * width * height;
  BlurColumnsAdjointKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, width, height, taps, radius, g_out, scratch);
  ES_CUDA_CHECK_LAUNCH("BlurColumnsAdjointKernel");
  BlurRowsAdjointKernel<<<GridBlocks(n, kThreads), kThreads>>>(
      n, width, taps, radius, scratch, g_in);
  ES_CUDA_CHECK_LAUNCH("BlurRowsAdjointKernel");
}

void BandAndSquare(long long n, const double* fine, const double* coarse,
                   double* high, double* square) {
  BandAndSquareKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, fine, coarse,
                                                             high, square);
  ES_CUDA_CHECK_LAUNCH("BandAndSquareKernel");
}

void AmplitudeTerms(int planes, int planes_per_mask, long long pixels,
                    const double* e_r, const double* e_i, const double* water,
                    const double* counts, ChannelFloors floors, double eps,
                    double scale, double* d_e, double* partials) {
  const int blocks = GridBlocks(pixels, kThreads);
  AmplitudeKernel<<<planes * blocks, kThreads>>>(
      pixels, blocks, planes_per_mask, e_r, e_i, water, counts, floors, eps,
      scale, d_e, partials);
  ES_CUDA_CHECK_LAUNCH("AmplitudeKernel");
}

void AddMotionGradient(long long pixels, const double* diff, const double* g,
                       double* dy) {
  AddMotionGradientKernel<<<GridBlocks(3 * pixels, kThreads), kThreads>>>(
      pixels, diff, g, dy);
  ES_CUDA_CHECK_LAUNCH("AddMotionGradientKernel");
}

void ScaleByTwice(long long n, const double* high, double* g) {
  ScaleByTwiceKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, high, g);
  ES_CUDA_CHECK_LAUNCH("ScaleByTwiceKernel");
}

void AddBandGradient(long long n, const double* fine, const double* coarse,
                     double* dy) {
  AddBandGradientKernel<<<GridBlocks(n, kThreads), kThreads>>>(n, fine, coarse,
                                                               dy);
  ES_CUDA_CHECK_LAUNCH("AddBandGradientKernel");
}

void AddRgbGradients(long long pixels, const OpponentBasis& basis,
                     const double* dy, float* d_a, float* d_b) {
  AddRgbGradientsKernel<<<GridBlocks(pixels, kThreads), kThreads>>>(
      pixels, basis, dy, d_a, d_b);
  ES_CUDA_CHECK_LAUNCH("AddRgbGradientsKernel");
}

void SumSegments(int segments, int blocks, const double* partials,
                 double* sums) {
  SumSegmentsKernel<<<GridBlocks(segments, kThreads), kThreads>>>(
      segments, blocks, partials, sums);
  ES_CUDA_CHECK_LAUNCH("SumSegmentsKernel");
}

}  // namespace cuda
}  // namespace es
