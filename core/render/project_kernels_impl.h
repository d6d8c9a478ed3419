// The batched float projection and its backward (project_kernels.h).
// Included only by project_kernels_{sse2,avx2,avx512}.cc, each compiled for
// its instruction set with ES_PROJECT_ISA naming its namespace. Everything
// here has internal linkage and calls no out-of-line library code, so no
// function compiled for AVX2 / AVX-512 can be merged into, or called from,
// code that runs on a CPU without it.
//
// Each kernel gathers a batch of Gaussians into one array per quantity
// (lane i = Gaussian begin + i), runs the maths as `omp simd` loops over
// the lanes, all branches turned into selects, and scatters the results.
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

#include "core/render/project_kernels.h"
#include "core/render/raster_constants.h"
#include "core/render/tile_kernels.h"

namespace es {
namespace ES_PROJECT_ISA {
namespace {

using F = float;
using D = double;
constexpr int kB = kProjectBatch;
constexpr int kMaxCoeffs = 16;  // SH degree 3

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
inline bool Finite(F x) { return x - x == 0.0f; }
inline bool FiniteD(D x) { return x - x == 0.0; }
inline F Min(F a, F b) { return a < b ? a : b; }
inline F Max(F a, F b) { return a > b ? a : b; }
inline int MinInt(int a, int b) { return a < b ? a : b; }
inline int MaxInt(int a, int b) { return a > b ? a : b; }

// ClampToInt(floor(v), 0, hi) of raster_project.cc (NaN gives 0): for
// v >= 0 the cast's truncation is the floor.
inline int FloorClamped(F v, int hi) {
  v = v > 0.0f ? v : 0.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  return static_cast<int>(v);
}
// ClampToInt(floor(v) + 1, 0, hi) and ClampToInt(ceil(v) + 1, 0, hi).
inline int FloorPlusOneClamped(F v, int hi) {
  v = v > -1.0f ? v : -1.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  const int i = static_cast<int>(v);
  return MinInt(i - (static_cast<F>(i) > v ? 1 : 0) + 1, hi);
}
inline int CeilPlusOneClamped(F v, int hi) {
  v = v > -1.0f ? v : -1.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  const int i = static_cast<int>(v);
  return MinInt(i + (static_cast<F>(i) < v ? 1 : 0) + 1, hi);
}

// The camera in float (the camera-space means are computed in double).
struct Camera {
  F r[9];
  F fx, fy, cx, cy, lim_x, lim_y;
  explicit Camera(const ProjectionInput& in)
      : fx(static_cast<F>(in.fx)), fy(static_cast<F>(in.fy)),
        cx(static_cast<F>(in.cx)), cy(static_cast<F>(in.cy)),
        lim_x(static_cast<F>(in.lim_x)), lim_y(static_cast<F>(in.lim_y)) {
    for (int i = 0; i < 9; ++i) r[i] = static_cast<F>(in.R[i]);
  }
};

// A batch's inputs, one array per quantity. Lanes past the batch's count
// repeat its first Gaussian, so every lane computes on real data.
struct Lanes {
  F p[3][kB];  // camera-space mean, R mean + t (in double, then rounded)
  F v[3][kB];  // mean - camera center (likewise)
  F q[4][kB];
  F log_scale[3][kB];
  F logit[kB];
};

void Gather(const ProjectionInput& in, int begin, int count, Lanes* l) {
  for (int i = 0; i < kB; ++i) {
    const int n = begin + (i < count ? i : 0);
    const double* m = in.means + 3 * static_cast<size_t>(n);
    for (int r = 0; r < 3; ++r) {
      l->p[r][i] = static_cast<F>(in.R[3 * r] * m[0] + in.R[3 * r + 1] * m[1] +
                                  in.R[3 * r + 2] * m[2] + in.t[r]);
      l->v[r][i] = static_cast<F>(m[r] - in.center[r]);
      l->log_scale[r][i] =
          static_cast<F>(in.log_scales[3 * static_cast<size_t>(n) + r]);
    }
    for (int c = 0; c < 4; ++c)
      l->q[c][i] = static_cast<F>(in.quats[4 * static_cast<size_t>(n) + c]);
    l->logit[i] = static_cast<F>(in.opacity_logits[n]);
  }
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

// The projection's intermediates shared by forward and backward.
struct Geometry {
  F valid[kB];  // 1 where the Gaussian is in front and not degenerate
  F q_unit[4][kB], q_norm[kB];
  F scale[3][kB];
  F rot[9][kB];  // R(q_unit), row-major
  F jw[6][kB];   // J R_cam, 2x3 row-major
  F t[6][kB];    // J R_cam R(q) diag(scale): cov2 = T T^T + dilation
  F a[kB], b[kB], c[kB];  // dilated 2D covariance
  D conic[3][kB];         // its inverse
  F xz[kB], yz[kB];          // x/z and y/z, clamped to the FOV
  F x_free[kB], y_free[kB];  // 1 where not clamped
};

void ComputeGeometry(const Camera& cam, const Lanes& l, Geometry* g) {
  const D dil = kCovarianceDilation;
  const F near = static_cast<F>(kNearPlane);
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F z = l.p[2][i];
    const F q0 = l.q[0][i], q1 = l.q[1][i], q2 = l.q[2][i], q3 = l.q[3][i];
    const F qn = Sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3);
    const F inv_qn = 1.0f / qn;
    const F w = q0 * inv_qn, x = q1 * inv_qn, y = q2 * inv_qn,
            zq = q3 * inv_qn;
    g->q_norm[i] = qn;
    g->q_unit[0][i] = w;
    g->q_unit[1][i] = x;
    g->q_unit[2][i] = y;
    g->q_unit[3][i] = zq;
    const F rot[9] = {1 - 2 * (y * y + zq * zq), 2 * (x * y - w * zq),
                      2 * (x * zq + w * y),      2 * (x * y + w * zq),
                      1 - 2 * (x * x + zq * zq), 2 * (y * zq - w * x),
                      2 * (x * zq - w * y),      2 * (y * zq + w * x),
                      1 - 2 * (x * x + y * y)};
    F s[3];
    for (int k = 0; k < 3; ++k) {
      s[k] = Exp(l.log_scale[k][i]);
      g->scale[k][i] = s[k];
    }
    for (int k = 0; k < 9; ++k) g->rot[k][i] = rot[k];
    const F raw_xz = l.p[0][i] / z, raw_yz = l.p[1][i] / z;
    const bool x_clamped = (raw_xz > 0 ? raw_xz : -raw_xz) > cam.lim_x;
    const bool y_clamped = (raw_yz > 0 ? raw_yz : -raw_yz) > cam.lim_y;
    const F xz = Min(Max(raw_xz, -cam.lim_x), cam.lim_x);
    const F yz = Min(Max(raw_yz, -cam.lim_y), cam.lim_y);
    g->xz[i] = xz;
    g->yz[i] = yz;
    g->x_free[i] = x_clamped ? 0.0f : 1.0f;
    g->y_free[i] = y_clamped ? 0.0f : 1.0f;
    const F jx = cam.fx / z, jy = cam.fy / z;
    F jw[6];
    for (int k = 0; k < 3; ++k) {
      jw[k] = jx * (cam.r[k] - xz * cam.r[6 + k]);
      jw[3 + k] = jy * (cam.r[3 + k] - yz * cam.r[6 + k]);
    }
    F t[6];
    for (int r = 0; r < 2; ++r)
      for (int k = 0; k < 3; ++k)
        t[3 * r + k] = (jw[3 * r] * rot[k] + jw[3 * r + 1] * rot[3 + k] +
                        jw[3 * r + 2] * rot[6 + k]) *
                       s[k];
    for (int k = 0; k < 6; ++k) {
      g->jw[k][i] = jw[k];
      g->t[k][i] = t[k];
    }
    // The 2D covariance and its inverse in double (see the top).
    D td[6];
    for (int k = 0; k < 6; ++k) td[k] = t[k];
    const D aa = td[0] * td[0] + td[1] * td[1] + td[2] * td[2];
    const D cc = td[3] * td[3] + td[4] * td[4] + td[5] * td[5];
    const D b = td[0] * td[3] + td[1] * td[4] + td[2] * td[5];
    const D c0 = td[1] * td[5] - td[2] * td[4];
    const D c1 = td[2] * td[3] - td[0] * td[5];
    const D c2 = td[0] * td[4] - td[1] * td[3];
    const D det = (c0 * c0 + c1 * c1 + c2 * c2) + dil * (aa + cc) + dil * dil;
    const D a = aa + dil, c = cc + dil;
    const D inv_det = 1.0 / det;
    g->a[i] = static_cast<F>(a);
    g->b[i] = static_cast<F>(b);
    g->c[i] = static_cast<F>(c);
    const D ca = c * inv_det, cb = -b * inv_det, cc2 = a * inv_det;
    g->conic[0][i] = ca;
    g->conic[1][i] = cb;
    g->conic[2][i] = cc2;
    F ok = z > near ? 1.0f : 0.0f;
    ok = qn > 0 ? ok : 0.0f;
    ok = det > 0 ? ok : 0.0f;
    ok = Finite(z) & Finite(qn) ? ok : 0.0f;
    ok = FiniteD(det) & FiniteD(ca) & FiniteD(cb) & FiniteD(cc2) ? ok : 0.0f;
    g->valid[i] = ok;
  }
}

// The unit view directions and the distances to the camera center.
void ViewDirections(const Lanes& l, F dir[3][kB], F len[kB]) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F x = l.v[0][i], y = l.v[1][i], z = l.v[2][i];
    const F d = Sqrt(x * x + y * y + z * z);
    const F inv = 1.0f / d;
    len[i] = d;
    dir[0][i] = x * inv;
    dir[1][i] = y * inv;
    dir[2][i] = z * inv;
  }
}

// Real SH constants of 3DGS (core/model/sh.cc).
constexpr F kC0 = 0.28209479177387814f;
constexpr F kC1 = 0.4886025119029199f;
constexpr F kC2[5] = {1.0925484305920792f, -1.0925484305920792f,
                      0.31539156525252005f, -1.0925484305920792f,
                      0.5462742152960396f};
constexpr F kC3[7] = {-0.5900435899266435f, 2.890611442640554f,
                      -0.4570457994644658f, 0.3731763325901154f,
                      -0.4570457994644658f, 1.445305721320277f,
                      -0.5900435899266435f};

// EvalShBasis per lane, all 16 functions (without a branch on the degree
// the loop vectorizes; those past the degree are not read).
void ShBasis(const F dir[3][kB], F basis[kMaxCoeffs][kB]) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F x = dir[0][i], y = dir[1][i], z = dir[2][i];
    const F xx = x * x, yy = y * y, zz = z * z;
    basis[0][i] = kC0;
    basis[1][i] = -kC1 * y;
    basis[2][i] = kC1 * z;
    basis[3][i] = -kC1 * x;
    basis[4][i] = kC2[0] * x * y;
    basis[5][i] = kC2[1] * y * z;
    basis[6][i] = kC2[2] * (2 * zz - xx - yy);
    basis[7][i] = kC2[3] * x * z;
    basis[8][i] = kC2[4] * (xx - yy);
    basis[9][i] = kC3[0] * y * (3 * xx - yy);
    basis[10][i] = kC3[1] * x * y * z;
    basis[11][i] = kC3[2] * y * (4 * zz - xx - yy);
    basis[12][i] = kC3[3] * z * (2 * zz - 3 * xx - 3 * yy);
    basis[13][i] = kC3[4] * x * (4 * zz - xx - yy);
    basis[14][i] = kC3[5] * z * (xx - yy);
    basis[15][i] = kC3[6] * x * (xx - 3 * yy);
  }
}

// ShBasisBackward per lane: d loss / d dir from d loss / d basis, all 16
// entries (zero past the degree's count: no branch, so it vectorizes).
void ShBasisBackward(const F dir[3][kB], const F g[kMaxCoeffs][kB],
                   F d_dir[3][kB]) {
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F x = dir[0][i], y = dir[1][i], z = dir[2][i];
    const F xx = x * x, yy = y * y, zz = z * z;
    F dx = 0, dy = 0, dz = 0;
    // Degree 1.
    dy += -kC1 * g[1][i];
    dz += kC1 * g[2][i];
    dx += -kC1 * g[3][i];
    // Degree 2.
    dx += kC2[0] * y * g[4][i];
    dy += kC2[0] * x * g[4][i];
    dy += kC2[1] * z * g[5][i];
    dz += kC2[1] * y * g[5][i];
    dx += -2 * kC2[2] * x * g[6][i];
    dy += -2 * kC2[2] * y * g[6][i];
    dz += 4 * kC2[2] * z * g[6][i];
    dx += kC2[3] * z * g[7][i];
    dz += kC2[3] * x * g[7][i];
    dx += 2 * kC2[4] * x * g[8][i];
    dy += -2 * kC2[4] * y * g[8][i];
    // Degree 3.
    dx += kC3[0] * 6 * x * y * g[9][i];
    dy += kC3[0] * (3 * xx - 3 * yy) * g[9][i];
    dx += kC3[1] * y * z * g[10][i];
    dy += kC3[1] * x * z * g[10][i];
    dz += kC3[1] * x * y * g[10][i];
    dx += kC3[2] * (-2 * x * y) * g[11][i];
    dy += kC3[2] * (4 * zz - xx - 3 * yy) * g[11][i];
    dz += kC3[2] * 8 * y * z * g[11][i];
    dx += kC3[3] * (-6 * x * z) * g[12][i];
    dy += kC3[3] * (-6 * y * z) * g[12][i];
    dz += kC3[3] * (6 * zz - 3 * xx - 3 * yy) * g[12][i];
    dx += kC3[4] * (4 * zz - 3 * xx - yy) * g[13][i];
    dy += kC3[4] * (-2 * x * y) * g[13][i];
    dz += kC3[4] * 8 * x * z * g[13][i];
    dx += kC3[5] * 2 * x * z * g[14][i];
    dy += kC3[5] * (-2 * y * z) * g[14][i];
    dz += kC3[5] * (xx - yy) * g[14][i];
    dx += kC3[6] * (3 * xx - 3 * yy) * g[15][i];
    dy += kC3[6] * (-6 * x * y) * g[15][i];
    d_dir[0][i] = dx;
    d_dir[1][i] = dy;
    d_dir[2][i] = dz;
  }
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

void Forward(const ProjectionInput& in, int begin, int count,
             ProjectedSplat* out, char* keep) {
  const Camera cam(in);
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  Lanes l;
  Gather(in, begin, count, &l);
  Geometry g;
  ComputeGeometry(cam, l, &g);
  F dir[3][kB], len[kB], basis[kMaxCoeffs][kB], sh[3 * kMaxCoeffs][kB],
      color[3][kB];
  ViewDirections(l, dir, len);
  ShBasis(dir, basis);
  GatherSh(in, begin, count, 3 * coeffs, sh);
  ShColors(coeffs, basis, sh, color);

  F mean[2][kB], opacity[kB], radius_f[kB], ok_f[kB];
  int box[8][kB];  // px0, px1, py0, py1, tile x0, x1, y0, y1
  const F min_alpha = static_cast<F>(kMinAlpha);
  const F tile = static_cast<F>(kTileSize);
  const int width = in.width, height = in.height;
  const int tiles_x = in.tiles_x, tiles_y = in.tiles_y;
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F o = 1.0f / (1.0f + Exp(-l.logit[i]));
    const F z = l.p[2][i];
    const F mx = cam.fx * l.p[0][i] / z + cam.cx;
    const F my = cam.fy * l.p[1][i] / z + cam.cy;
    const F a = g.a[i], b = g.b[i], c = g.c[i];
    const F half = 0.5f * (a - c);
    const F lambda = 0.5f * (a + c) + Sqrt(half * half + b * b);
    // ceil(3 sqrt(lambda)), capped at 1e9 as the output (then the cast's
    // truncation is exact and SSE2 needs no ceil instruction).
    const F reach = 3.0f * Sqrt(lambda);
    const F capped = Min(reach, 1e9f);
    const int whole = static_cast<int>(capped);
    const F radius = static_cast<F>(whole + (static_cast<F>(whole) < capped));
    // The alpha box (raster_project.cc): half-widths sqrt(2 log(o /
    // kMinAlpha) cov_xx), likewise in y, and a one-pixel margin.
    const F level = 2.0f * Log(Max(o / min_alpha, 1.0f));
    const F ex = Sqrt(level * a), ey = Sqrt(level * c);
    const int px0 = FloorClamped(mx - ex - 0.5f, width);
    const int px1 = CeilPlusOneClamped(mx + ex - 0.5f, width);
    const int py0 = FloorClamped(my - ey - 0.5f, height);
    const int py1 = CeilPlusOneClamped(my + ey - 0.5f, height);
    const int tx0 = FloorClamped((mx - radius) / tile, tiles_x);
    const int tx1 = FloorPlusOneClamped((mx + radius) / tile, tiles_x);
    const int ty0 = FloorClamped((my - radius) / tile, tiles_y);
    const int ty1 = FloorPlusOneClamped((my + radius) / tile, tiles_y);
    const int bx0 = MaxInt(tx0, px0 / kTileSize);
    const int by0 = MaxInt(ty0, py0 / kTileSize);
    const int bx1 = MinInt(tx1, (px1 + kTileSize - 1) / kTileSize);
    const int by1 = MinInt(ty1, (py1 + kTileSize - 1) / kTileSize);
    // One select per test, each on a 32-bit lane (a chain of bools would
    // be 8-bit lanes, which GCC does not mix with these).
    F ok = g.valid[i];
    ok = o >= min_alpha ? ok : 0.0f;
    ok = Finite(mx) & Finite(my) & Finite(reach) ? ok : 0.0f;
    ok = tx0 < tx1 ? ok : 0.0f;
    ok = ty0 < ty1 ? ok : 0.0f;
    ok = bx0 < bx1 ? ok : 0.0f;
    ok = by0 < by1 ? ok : 0.0f;
    ok = px0 < px1 ? ok : 0.0f;
    ok = py0 < py1 ? ok : 0.0f;
    for (int ch = 0; ch < 3; ++ch) ok = Finite(color[ch][i]) ? ok : 0.0f;
    ok_f[i] = ok;
    mean[0][i] = mx;
    mean[1][i] = my;
    opacity[i] = o;
    radius_f[i] = radius;
    box[0][i] = px0;
    box[1][i] = px1;
    box[2][i] = py0;
    box[3][i] = py1;
    box[4][i] = bx0;
    box[5][i] = bx1;
    box[6][i] = by0;
    box[7][i] = by1;
  }
  for (int i = 0; i < count; ++i) {
    keep[i] = ok_f[i] != 0.0f;
    if (!keep[i]) continue;
    ProjectedSplat& p = out[i];
    p.mean2d[0] = mean[0][i];
    p.mean2d[1] = mean[1][i];
    for (int k = 0; k < 3; ++k) p.conic[k] = g.conic[k][i];
    p.depth = l.p[2][i];
    p.opacity = opacity[i];
    for (int ch = 0; ch < 3; ++ch) p.color[ch] = Max(color[ch][i], 0.0f);
    p.radius = static_cast<int>(radius_f[i]);
    p.px0 = box[0][i];
    p.px1 = box[1][i];
    p.py0 = box[2][i];
    p.py1 = box[3][i];
    p.tile_x0 = box[4][i];
    p.tile_x1 = box[5][i];
    p.tile_y0 = box[6][i];
    p.tile_y1 = box[7][i];
  }
}

void Backward(const ProjectionInput& in, int begin, int count,
              const char* keep, const double* grad2d, int stride,
              const ProjectionGradients& out) {
  const Camera cam(in);
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  Lanes l;
  Gather(in, begin, count, &l);
  Geometry g;
  ComputeGeometry(cam, l, &g);
  // The 2D gradients: mean (2), conic (3), opacity, r, g, b, depth.
  constexpr int kTerms = kTileGradHead + 4;
  F pg[kTerms][kB];
  D pg_conic[3][kB];
  for (int i = 0; i < kB; ++i) {
    const double* row = grad2d + static_cast<size_t>(stride) *
                                     (i < count ? i : 0);
    for (int c = 0; c < kTerms; ++c) pg[c][i] = static_cast<F>(row[c]);
    for (int c = 0; c < 3; ++c) pg_conic[c][i] = row[2 + c];
  }

  F g_mean[3][kB], g_log_scale[3][kB], g_quat[4][kB], g_logit[kB];
#pragma omp simd
  for (int i = 0; i < kB; ++i) {
    const F z = l.p[2][i], x = l.p[0][i], y = l.p[1][i];
    // Conic -> dilated covariance: dS = -C dC C (dC symmetric, its
    // off-diagonal half the b gradient).
    // In double (see the top): for a needle dS is large across it and
    // the part of dT along it is a difference of such terms.
    const D ca = g.conic[0][i], cb = g.conic[1][i], cc = g.conic[2][i];
    const D g0 = pg_conic[0][i], gh = 0.5 * pg_conic[1][i],
            g2 = pg_conic[2][i];
    const D m00 = ca * g0 + cb * gh, m01 = ca * gh + cb * g2;
    const D m10 = cb * g0 + cc * gh, m11 = cb * gh + cc * g2;
    const D s00 = -(m00 * ca + m01 * cb), s01 = -(m00 * cb + m01 * cc);
    const D s11 = -(m10 * cb + m11 * cc);
    // cov2 = T T^T + dilation: dT = 2 dS T; T = JW M with M = R(q) S.
    F jw[6], rot[9], s[3];
    for (int k = 0; k < 6; ++k) jw[k] = g.jw[k][i];
    for (int k = 0; k < 9; ++k) rot[k] = g.rot[k][i];
    for (int k = 0; k < 3; ++k) s[k] = g.scale[k][i];
    F gt[6];
    for (int k = 0; k < 3; ++k) {
      const D t0 = g.t[k][i], t1 = g.t[3 + k][i];
      gt[k] = static_cast<F>(2 * (s00 * t0 + s01 * t1));
      gt[3 + k] = static_cast<F>(2 * (s01 * t0 + s11 * t1));
    }
    // d JW = dT M^T; d M = JW^T dT.
    F g_jw[6];
    for (int r = 0; r < 2; ++r)
      for (int k = 0; k < 3; ++k)
        g_jw[3 * r + k] = gt[3 * r] * rot[3 * k] * s[0] +
                          gt[3 * r + 1] * rot[3 * k + 1] * s[1] +
                          gt[3 * r + 2] * rot[3 * k + 2] * s[2];
    F g_m[9];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        g_m[3 * r + k] = jw[r] * gt[k] + jw[3 + r] * gt[3 + k];
    // d J = d JW R_cam^T: the entries J depends on.
    const auto g_j = [&](int row, int col) {
      return g_jw[3 * row] * cam.r[3 * col] +
             g_jw[3 * row + 1] * cam.r[3 * col + 1] +
             g_jw[3 * row + 2] * cam.r[3 * col + 2];
    };
    const F gj00 = g_j(0, 0), gj02 = g_j(0, 2), gj11 = g_j(1, 1),
            gj12 = g_j(1, 2);
    const F z2 = z * z, z3 = z2 * z;
    const F gm0 = pg[0][i], gm1 = pg[1][i];
    F gx = cam.fx / z * gm0;
    F gy = cam.fy / z * gm1;
    F gz = -(cam.fx * x * gm0 + cam.fy * y * gm1) / z2 +
           pg[kTileGradHead + 3][i];
    gz -= cam.fx / z2 * gj00 + cam.fy / z2 * gj11;
    // A coordinate clamped to the FOV passes no gradient to x or y.
    const bool x_free = g.x_free[i] != 0.0f, y_free = g.y_free[i] != 0.0f;
    gx -= x_free ? cam.fx / z2 * gj02 : 0.0f;
    gz += x_free ? 2 * cam.fx * x / z3 * gj02 : cam.fx * g.xz[i] / z2 * gj02;
    gy -= y_free ? cam.fy / z2 * gj12 : 0.0f;
    gz += y_free ? 2 * cam.fy * y / z3 * gj12 : cam.fy * g.yz[i] / z2 * gj12;
    for (int k = 0; k < 3; ++k)
      g_mean[k][i] = cam.r[k] * gx + cam.r[3 + k] * gy + cam.r[6 + k] * gz;
    // M = R(q) diag(scale).
    F g_rot[9];
    for (int k = 0; k < 3; ++k) {
      F g_scale = 0;
      for (int r = 0; r < 3; ++r) {
        g_scale += g_m[3 * r + k] * rot[3 * r + k];
        g_rot[3 * r + k] = g_m[3 * r + k] * s[k];
      }
      g_log_scale[k][i] = g_scale * s[k];
    }
    // d (w, x, y, z) of the unit quaternion (RotationBackward), then through
    // the normalization.
    const F w = g.q_unit[0][i], qx = g.q_unit[1][i], qy = g.q_unit[2][i],
            qz = g.q_unit[3][i];
    const auto gr = [&](int r, int c) { return g_rot[3 * r + c]; };
    F d[4];
    d[0] = 2 * (-qz * gr(0, 1) + qy * gr(0, 2) + qz * gr(1, 0) -
                qx * gr(1, 2) - qy * gr(2, 0) + qx * gr(2, 1));
    d[1] = 2 * (qy * gr(0, 1) + qz * gr(0, 2) + qy * gr(1, 0) -
                2 * qx * gr(1, 1) - w * gr(1, 2) + qz * gr(2, 0) +
                w * gr(2, 1) - 2 * qx * gr(2, 2));
    d[2] = 2 * (-2 * qy * gr(0, 0) + qx * gr(0, 1) + w * gr(0, 2) +
                qx * gr(1, 0) + qz * gr(1, 2) - w * gr(2, 0) +
                qz * gr(2, 1) - 2 * qy * gr(2, 2));
    d[3] = 2 * (-2 * qz * gr(0, 0) - w * gr(0, 1) + qx * gr(0, 2) +
                w * gr(1, 0) - 2 * qz * gr(1, 1) + qy * gr(1, 2) +
                qx * gr(2, 0) + qy * gr(2, 1));
    const F dot = d[0] * w + d[1] * qx + d[2] * qy + d[3] * qz;
    const F inv_qn = 1.0f / g.q_norm[i];
    g_quat[0][i] = (d[0] - dot * w) * inv_qn;
    g_quat[1][i] = (d[1] - dot * qx) * inv_qn;
    g_quat[2][i] = (d[2] - dot * qy) * inv_qn;
    g_quat[3][i] = (d[3] - dot * qz) * inv_qn;
    // sigmoid' = o (1 - o) = e / (1 + e)^2, e = exp(-logit), without the
    // cancellation of 1 - o near 1.
    const F e = Exp(-l.logit[i]);
    g_logit[i] = pg[5][i] * (e / ((1.0f + e) * (1.0f + e)));
  }

  // Colour: SH + 0.5, clamped below at 0 (no gradient where clamped).
  F dir[3][kB], len[kB], basis[kMaxCoeffs][kB], sh[3 * kMaxCoeffs][kB],
      color[3][kB];
  ViewDirections(l, dir, len);
  ShBasis(dir, basis);
  GatherSh(in, begin, count, 3 * coeffs, sh);
  ShColors(coeffs, basis, sh, color);
  F g_color[3][kB];
  for (int ch = 0; ch < 3; ++ch) {
#pragma omp simd
    for (int i = 0; i < kB; ++i)
      g_color[ch][i] = color[ch][i] < 0 ? 0.0f : pg[kTileGradHead + ch][i];
  }
  F g_basis[kMaxCoeffs][kB];
  for (int k = coeffs; k < kMaxCoeffs; ++k)
    for (int i = 0; i < kB; ++i) g_basis[k][i] = 0.0f;
  for (int k = 0; k < coeffs; ++k) {
#pragma omp simd
    for (int i = 0; i < kB; ++i)
      g_basis[k][i] = sh[3 * k][i] * g_color[0][i] +
                      sh[3 * k + 1][i] * g_color[1][i] +
                      sh[3 * k + 2][i] * g_color[2][i];
  }
  if (in.sh_degree > 0) {
    F g_dir[3][kB];
    ShBasisBackward(dir, g_basis, g_dir);
#pragma omp simd
    for (int i = 0; i < kB; ++i) {
      const F dot = g_dir[0][i] * dir[0][i] + g_dir[1][i] * dir[1][i] +
                    g_dir[2][i] * dir[2][i];
      const F inv_len = 1.0f / len[i];
      for (int k = 0; k < 3; ++k)
        g_mean[k][i] += (g_dir[k][i] - dot * dir[k][i]) * inv_len;
    }
  }

  for (int i = 0; i < count; ++i) {
    if (!keep[i]) continue;
    const size_t n = static_cast<size_t>(begin) + i;
    for (int k = 0; k < 3; ++k) {
      out.means[3 * n + k] = g_mean[k][i];
      out.log_scales[3 * n + k] = g_log_scale[k][i];
    }
    for (int k = 0; k < 4; ++k) out.quats[4 * n + k] = g_quat[k][i];
    out.opacity_logits[n] = g_logit[i];
    double* g_sh = out.sh + 3 * static_cast<size_t>(coeffs) * n;
    for (int k = 0; k < coeffs; ++k)
      for (int ch = 0; ch < 3; ++ch)
        g_sh[3 * k + ch] = basis[k][i] * g_color[ch][i];
  }
}

const ProjectKernelSet kKernels = {&Forward, &Backward};

}  // namespace

const ProjectKernelSet& Kernels() { return kKernels; }

}  // namespace ES_PROJECT_ISA
}  // namespace es
