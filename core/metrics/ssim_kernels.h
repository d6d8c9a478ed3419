#ifndef EULERSPLAT_CORE_METRICS_SSIM_KERNELS_H_
#define EULERSPLAT_CORE_METRICS_SSIM_KERNELS_H_

// SSIM's blurs and per-pixel terms, compiled once per instruction set
// (ssim_kernels_{sse2,avx2,avx512}.cc from the one source in
// ssim_kernels_impl.h) and picked at run time. Callers use
// core/metrics/ssim.h, which owns the buffers; these see raw pointers only.

#include "core/base/simd_level.h"

namespace es {

// SSIM's window and constants (image_metrics.h says how they are used).
constexpr int kSsimWindow = 11;
constexpr int kSsimRadius = 5;  // of the 11 x 11 window
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;
constexpr double kSsimC2 = 0.03 * 0.03;

// Images are H x W x C, interleaved, row-major: rows of
// row_len = W C values, n = H row_len in all. The window is separable:
// each pass blurs rows (a value's neighbours are C apart), then columns,
// with zero padding.
template <typename T>
struct SsimPass {
  int rows = 0, row_len = 0, channels = 0;
  T weights[kSsimRadius + 1] = {};  // the 1D window, centre tap first

  // TargetStats reads y; Evaluate reads x, y and the target's mu_y, var_y.
  const double* x = nullptr;
  const T* y = nullptr;
  const T* mu_y = nullptr;
  const T* var_y = nullptr;

  // Evaluate's optional outputs (nullptr: not wanted).
  double* map = nullptr;  // per-value SSIM
  double* d_x = nullptr;  // grad_scale * d mean SSIM / d x (+ the L1 part)
  double grad_scale = 1;
  // The L1 term fused in (it reads the same values): if set, receives
  // mean |x - y|, and d_x also gets l1_grad_scale * sign(x - y) / n.
  double* l1 = nullptr;
  double l1_grad_scale = 0;

  // Scratch, sized by SsimScratchLayout: three row-blurred planes of n
  // values; the gradient terms as three planes of rows padded by
  // kSsimRadius C zeros on both sides (padded_len = row_len +
  // 2 kSsimRadius C, the padding zero on entry and kept so); per thread
  // thread_stride values (three padded rows, then three blurred rows); one
  // row of zeros; two doubles per row.
  T* planes = nullptr;
  T* grad_terms = nullptr;
  T* thread_rows = nullptr;
  long long thread_stride = 0;
  const T* zero_row = nullptr;
  double* row_sums = nullptr;
  bool parallel = true;  // split rows over OpenMP threads
};

template <typename T>
struct SsimKernelSet {
  // mu = G * y and var = G * y^2 - mu^2 (n values each).
  void (*target_stats)(const SsimPass<T>& pass, T* mu, T* var);
  // The mean SSIM of x against y; fills map and d_x when they are set.
  double (*evaluate)(const SsimPass<T>& pass);
};

template <typename T>
const SsimKernelSet<T>& SsimKernels(SimdLevel level);

#define ES_DECLARE_SSIM_KERNELS(isa)           \
  namespace isa {                              \
  const SsimKernelSet<float>& FloatKernels();  \
  const SsimKernelSet<double>& DoubleKernels(); \
  }
ES_DECLARE_SSIM_KERNELS(ssim_sse2)
ES_DECLARE_SSIM_KERNELS(ssim_avx2)
ES_DECLARE_SSIM_KERNELS(ssim_avx512)
#undef ES_DECLARE_SSIM_KERNELS

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_SSIM_KERNELS_H_
