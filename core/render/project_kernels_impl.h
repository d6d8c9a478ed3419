// The batched float projection and its backward (project_kernels.h).
// Included only by project_kernels_{sse2,avx2,avx512}.cc, each compiled for
// its instruction set with ES_PROJECT_ISA naming its namespace. Everything
// here has internal linkage and calls no out-of-line library code, so no
// function compiled for AVX2 / AVX-512 can be merged into, or called from,
// code that runs on a CPU without it.
//
// Each kernel gathers a batch of Gaussians into one array per quantity
// (lane i = Gaussian begin + i), runs the per-lane maths of
// projection_math.inc (which the device's cuda/project.cu runs too) as
// `omp simd` loops over the lanes, and scatters the results.
// The formulas are ProjectSplat's and ProjectSplatBackward's
// (raster_project.cc), in float except one step: the dilated 2D covariance
// cov2 = T T^T + d (T = J W R(q) S, its 2x3 factor, d the dilation), its
// inverse (the conic) and, in the backward, d T = 2 (-C dC C) T from the
// conic's gradient dC run in double. For a needle (eigenvalues of cov2
// 1e4-1e5 apart) those are differences of large, nearly equal terms: in
// float the gradient along the needle's long axis drowned in rounding (a few
// % of its log-scale gradients at 2000:1), and T's columns, each accurate in
// float, keep it in double. The determinant is det(T T^T) + d tr(T T^T) +
// d^2 with det(T T^T) = |T_0 x T_1|^2, never negative; the largest
// eigenvalue uses mid^2 - det = ((a - c) / 2)^2 + b^2 likewise.

#if !defined(ES_PROJECT_ISA)
#error "define ES_PROJECT_ISA before this header"
#endif

// Selects instead of branches (GCC keeps branches while a comparison might
// raise a floating-point exception flag): values are unchanged and nothing
// here reads the flags. The files build with -fno-math-errno
// (CMakeLists.txt), so sqrt is one instruction too.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-trapping-math")
#endif

#include <cstdint>
#include <cstring>

#include "core/base/host_device.h"
#include "core/render/project_kernels.h"
#include "core/render/raster_constants.h"
#include "core/render/tile_kernels.h"

namespace es {
namespace ES_PROJECT_ISA {
namespace {

using F = float;
constexpr int kB = kProjectBatch;

#include "core/render/exp_polynomial.inc"

// exp(x) for float x, clamped to the normal range (ExpPolynomial).
inline F Exp(F x) {
  x = x > -87.0f ? x : -87.0f;
  return ExpPolynomial(x < 88.0f ? x : 88.0f);
}

// log(x) for finite normal float x > 0: Cephes' logf (about 1 ulp).
inline F Log(F x) {
  int32_t bits;
  std::memcpy(&bits, &x, sizeof(bits));
  F e = static_cast<F>((bits >> 23) - 126);  // x = m 2^e, m in [0.5, 1)
  bits = (bits & 0x007fffff) | 0x3f000000;
  F m;
  std::memcpy(&m, &bits, sizeof(m));
  const bool low = m < 0.707106781186547524f;
  e = low ? e - 1.0f : e;
  m = low ? m + m - 1.0f : m - 1.0f;
  const F z = m * m;
  F y = 7.0376836292e-2f;
  y = y * m - 1.1514610310e-1f;
  y = y * m + 1.1676998740e-1f;
  y = y * m - 1.2420140846e-1f;
  y = y * m + 1.4249322787e-1f;
  y = y * m - 1.6668057665e-1f;
  y = y * m + 2.0000714765e-1f;
  y = y * m - 2.4999993993e-1f;
  y = y * m + 3.3333331174e-1f;
  y = y * m * z;
  y += -2.12194440e-4f * e;
  y += -0.5f * z;
  return m + y + 0.693359375f * e;
}

inline F Sqrt(F x) { return __builtin_sqrtf(x); }

#include "core/render/projection_math.inc"

// Gaussian begin + i into lane i; lanes past the batch's count repeat its
// first Gaussian, so every lane computes on real data.
void Gather(const ProjectionInput& in, int begin, int count, Lanes<kB>* l) {
  for (int i = 0; i < kB; ++i)
    GatherLane(in, begin + (i < count ? i : 0), i, l);
}

// The batch's SH coefficients, sh[3k + ch][lane].
void GatherSh(const ProjectionInput& in, int begin, int count, int coeffs,
              F sh[3 * kMaxCoeffs][kB]) {
  for (int i = 0; i < kB; ++i) {
    const int n = begin + (i < count ? i : 0);
    const double* src = in.sh + static_cast<size_t>(coeffs) * n;
    for (int j = 0; j < coeffs; ++j) sh[j][i] = static_cast<F>(src[j]);
  }
}

void ComputeGeometry(const Camera& cam, const Lanes<kB>& l, Geometry<kB>* g) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) GeometryLane(cam, l, i, g);
}

void ViewDirections(const Lanes<kB>& l, F dir[3][kB], F len[kB]) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) ViewDirectionLane(l, i, dir, len);
}

void ShBasis(const F dir[3][kB], F basis[kMaxCoeffs][kB]) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) ShBasisLane(dir, i, basis);
}

// color[ch] = 0.5 + sum_k basis[k] sh[3k + ch], before the clamp at 0.
void ShColors(int coeffs, const F basis[kMaxCoeffs][kB],
              const F sh[3 * kMaxCoeffs][kB], F color[3][kB]) {
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < kB; ++i) color[ch][i] = 0.5f;
  for (int k = 0; k < coeffs; ++k)
    for (int ch = 0; ch < 3; ++ch) {
#pragma omp simd
      for (int i = 0; i < kB; ++i)
        color[ch][i] += basis[k][i] * sh[3 * k + ch][i];
    }
}

// A batch's inputs, geometry, view directions, SH and colours: what
// forward and backward both compute first.
struct Batch {
  Camera cam;
  int coeffs;
  Lanes<kB> l;
  Geometry<kB> g;
  F dir[3][kB], len[kB], basis[kMaxCoeffs][kB], sh[3 * kMaxCoeffs][kB],
      color[3][kB];
  Batch(const ProjectionInput& in, int begin, int count)
      : cam(in), coeffs((in.sh_degree + 1) * (in.sh_degree + 1)) {
    Gather(in, begin, count, &l);
    ComputeGeometry(cam, l, &g);
    ViewDirections(l, dir, len);
    ShBasis(dir, basis);
    GatherSh(in, begin, count, 3 * coeffs, sh);
    ShColors(coeffs, basis, sh, color);
  }
};

void Forward(const ProjectionInput& in, int begin, int count,
             ProjectedSplat* out, char* keep) {
  const Batch b(in, begin, count);
  Footprint<kB> fp;
#pragma omp simd
  for (int i = 0; i < kB; ++i) FootprintLane(b.cam, b.l, b.g, b.color, i, &fp);
  for (int i = 0; i < count; ++i) {
    keep[i] = fp.ok[i] != 0.0f;
    if (!keep[i]) continue;
    ProjectedSplat& p = out[i];
    p.mean2d[0] = fp.mean[0][i];
    p.mean2d[1] = fp.mean[1][i];
    for (int k = 0; k < 3; ++k) p.conic[k] = b.g.conic[k][i];
    p.depth = b.l.p[2][i];
    p.opacity = fp.opacity[i];
    for (int ch = 0; ch < 3; ++ch) p.color[ch] = Max(b.color[ch][i], 0.0f);
    p.radius = static_cast<int>(fp.radius[i]);
    p.px0 = fp.box[0][i];
    p.px1 = fp.box[1][i];
    p.py0 = fp.box[2][i];
    p.py1 = fp.box[3][i];
    p.tile_x0 = fp.box[4][i];
    p.tile_x1 = fp.box[5][i];
    p.tile_y0 = fp.box[6][i];
    p.tile_y1 = fp.box[7][i];
  }
}

void Backward(const ProjectionInput& in, int begin, int count, const char* keep,
              const double* grad2d, int stride,
              const ProjectionGradients& out) {
  const Batch b(in, begin, count);
  const int coeffs = b.coeffs;
  ScreenGradients<kB> sg;
  for (int i = 0; i < kB; ++i)
    GatherGradientLane(
        grad2d + static_cast<size_t>(stride) * (i < count ? i : 0), i, &sg);
  GeometryGradients<kB> gg;
#pragma omp simd
  for (int i = 0; i < kB; ++i)
    GeometryBackwardLane(b.cam, b.l, b.g, sg, i, &gg);

  // Colour: SH + 0.5, clamped below at 0 (no gradient where clamped).
  F g_color[3][kB];
  for (int ch = 0; ch < 3; ++ch) {
#pragma omp simd
    for (int i = 0; i < kB; ++i)
      g_color[ch][i] = b.color[ch][i] < 0 ? 0.0f : sg.pg[kTileGradHead + ch][i];
  }
  F g_basis[kMaxCoeffs][kB];
  for (int k = coeffs; k < kMaxCoeffs; ++k)
    for (int i = 0; i < kB; ++i) g_basis[k][i] = 0.0f;
  for (int k = 0; k < coeffs; ++k) {
#pragma omp simd
    for (int i = 0; i < kB; ++i)
      g_basis[k][i] = b.sh[3 * k][i] * g_color[0][i] +
                      b.sh[3 * k + 1][i] * g_color[1][i] +
                      b.sh[3 * k + 2][i] * g_color[2][i];
  }
  if (in.sh_degree > 0) {
#pragma omp simd
    for (int i = 0; i < kB; ++i)
      ViewDirectionBackwardLane(b.dir, b.len, g_basis, i, gg.mean);
  }

  for (int i = 0; i < count; ++i) {
    if (!keep[i]) continue;
    const size_t n = static_cast<size_t>(begin) + i;
    for (int k = 0; k < 3; ++k) {
      out.means[3 * n + k] = gg.mean[k][i];
      out.log_scales[3 * n + k] = gg.log_scale[k][i];
    }
    for (int k = 0; k < 4; ++k) out.quats[4 * n + k] = gg.quat[k][i];
    out.opacity_logits[n] = gg.logit[i];
    double* g_sh = out.sh + 3 * static_cast<size_t>(coeffs) * n;
    for (int k = 0; k < coeffs; ++k)
      for (int ch = 0; ch < 3; ++ch)
        g_sh[3 * k + ch] = b.basis[k][i] * g_color[ch][i];
  }
}

const ProjectKernelSet kKernels = {&Forward, &Backward};

}  // namespace

const ProjectKernelSet& Kernels() { return kKernels; }

}  // namespace ES_PROJECT_ISA
}  // namespace es
