#ifndef EULERSPLAT_COSTS_WATER_KERNELS_H_
#define EULERSPLAT_COSTS_WATER_KERNELS_H_

// The separable blurs of the water losses (costs/water_image_filters.h)
// and their adjoints, the energy loss's per-pixel terms and the texture
// loss's projections, compiled once per instruction set
// (water_kernels_{sse2,avx2,avx512}.cc from the one source in
// water_kernels_impl.h) and picked at run time. Every set sums each
// output's terms in the same order without fused multiply-adds, so all
// give the same bits: a run resumed on another CPU goes on unchanged.
//
// Images are row-major doubles, w x h; k holds the 2 r + 1 taps of a 1D
// kernel; borders are clamped: out[i] = sum_j k[j] in[clamp(i + j - r)].

#include "core/base/simd_level.h"

namespace es {

// What a pass needs besides its images, sized by the caller for the
// kernel's radius r and the image's width w.
struct WaterFilterScratch {
  const double** sources = nullptr;  // (2 r + 1)^2 row pointers
  double* coefficients = nullptr;    // (2 r + 1)^2 taps
  double* line = nullptr;            // w + 2 r values
};

// The texture loss's features and their projections
// (costs/water_texture_loss.h): pixel i's feature 9 b + o is band b's
// value at taps[b % levels][9 i + o], its 3 x 3 neighbourhood at that
// band's spacing.
struct TextureProjection {
  const double* const* bands = nullptr;  // `count` images
  int count = 0, levels = 0;
  const int* const* taps = nullptr;    // per level, 9 n pixel indices
  long n = 0;                          // pixels
  const double* directions = nullptr;  // 9 count x projections, col-major
  int projections = 0;
};

struct WaterKernelSet {
  // Along x, then along y.
  void (*blur_rows)(const double* in, int w, int h, const double* k, int r,
                    const WaterFilterScratch& scratch, double* out);
  void (*blur_columns)(const double* in, int w, int h, const double* k, int r,
                       const WaterFilterScratch& scratch, double* out);
  // Their adjoints: g_in = B^T g_out, exact at the borders.
  void (*blur_rows_adjoint)(const double* g_out, int w, int h, const double* k,
                            int r, const WaterFilterScratch& scratch,
                            double* g_in);
  void (*blur_columns_adjoint)(const double* g_out, int w, int h,
                               const double* k, int r,
                               const WaterFilterScratch& scratch, double* g_in);
  // The energy loss's per-pixel amplitude terms over n pixels: where
  // water[p] != 0, a = sqrt(max(e_rendered[p], 0) + floor), b =
  // sqrt(max(e_input[p], 0) + eps), term[p] = |a - b| and d_energy[p] =
  // scale sign(a - b) / (2 a count); elsewhere both 0.
  void (*amplitude_terms)(const double* e_rendered, const double* e_input,
                          const double* water, long n, double floor, double eps,
                          double scale, double count, double* term,
                          double* d_energy);
  // out(i, j) = sum over the features f in order of feature f of pixel i
  // times directions(f, j), for pixels i in [begin, end); out is n x
  // projections, col-major.
  void (*project)(const TextureProjection& p, long begin, long end,
                  double* out);
  // The adjoint for band b: d_band[taps[9 i + o]] += sum_j d_proj(i, j)
  // directions(9 b + o, j) (summed in j order), for pixel i = 0 .. n - 1
  // in order, o = 0 .. 8 in order, once per 16 directions (then 4, then
  // 1); d_proj is n x projections, col-major.
  void (*project_adjoint)(const TextureProjection& p, int b,
                          const double* d_proj, double* d_band);
};

// The set for `level` (kAuto: the best this CPU runs).
const WaterKernelSet& WaterKernels(SimdLevel level = SimdLevel::kAuto);

#define ES_DECLARE_WATER_KERNELS(isa) \
  namespace isa {                     \
  const WaterKernelSet& Kernels();    \
  }
ES_DECLARE_WATER_KERNELS(water_kernels_sse2)
ES_DECLARE_WATER_KERNELS(water_kernels_avx2)
ES_DECLARE_WATER_KERNELS(water_kernels_avx512)
#undef ES_DECLARE_WATER_KERNELS

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_KERNELS_H_
