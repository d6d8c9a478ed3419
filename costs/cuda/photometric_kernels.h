#ifndef EULERSPLAT_COSTS_CUDA_PHOTOMETRIC_KERNELS_H_
#define EULERSPLAT_COSTS_CUDA_PHOTOMETRIC_KERNELS_H_

// The device photometric loss's kernels (photometric.cu), as
// DevicePhotometricLoss launches them: plain types only. Images are H x W x
// C floats, interleaved, row-major (n = H W C values); planes are n values
// each, one after another. All pointers are device pointers.

namespace es {
namespace cuda {

// The 1D window, centre tap first (kSsimRadius + 1 taps), as the CPU's.
struct SsimWindow {
  float w[6];
};

// Blocks of the value-parallel passes, each writing one partial sum pair.
int PhotometricBlocks(long long n);

// planes[0..4] = x, x^2, x y, y, y^2.
void SsimProducts(long long n, const float* x, const float* y,
                  float* planes);
// Blurs `count` planes with the window, zero padded: along rows into
// scratch, then down columns into out.
void SsimBlur(int count, int rows, int row_len, int channels,
              const SsimWindow& window, const float* planes, float* scratch,
              float* out);
// From the blurred planes (G x, G x^2, G x y, G y, G y^2): per value the
// SSIM and, with terms set, its gradient terms (3 planes, already / n);
// partials[2 b], [2 b + 1]: block b's sums of SSIM and of |x - y|.
void SsimTerms(long long n, const float* blurred, const float* x,
               const float* y, float* terms, double* partials);
// d = ssim_scale (G ga + 2 x G gb + y G gc) + l1_scale sign(x - y), from
// the blurred terms.
void SsimGradient(long long n, const float* blurred_terms, const float* x,
                  const float* y, double ssim_scale, double l1_scale,
                  float* d);
// Without SSIM: partials[2 b + 1] sums |x - y| (partials[2 b] = 0); with d
// set, d = l1_scale sign(x - y).
void L1Terms(long long n, const float* x, const float* y, double l1_scale,
             float* d, double* partials);
// sums[0], sums[1]: the partial sums of `blocks` blocks, in block order.
void SumPartials(int blocks, const double* partials, double* sums);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_PHOTOMETRIC_KERNELS_H_
