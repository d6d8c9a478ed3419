// The projection of Gaussians to the screen and its backward on the device,
// one thread per Gaussian: the float kernels of
// core/render/project_kernels_impl.h, formula for formula (their comments
// say why each step is done as it is), with the library exp and log where
// the CPU has its own polynomials.

#include "core/base/cuda/cuda_check.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

using F = float;
using D = double;
constexpr int kThreads = 256;
constexpr int kMaxCoeffs = 16;  // SH degree 3

__device__ inline F Exp(F x) {  // the CPU clamps to the normal range
  x = x > -87.0f ? x : -87.0f;
  return expf(x < 88.0f ? x : 88.0f);
}
__device__ inline bool Finite(F x) { return x - x == 0.0f; }
__device__ inline bool FiniteD(D x) { return x - x == 0.0; }
__device__ inline F Min(F a, F b) { return a < b ? a : b; }
__device__ inline F Max(F a, F b) { return a > b ? a : b; }

// The clamped casts of project_kernels_impl.h (NaN gives 0 or the low end).
__device__ inline int FloorClamped(F v, int hi) {
  v = v > 0.0f ? v : 0.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  return static_cast<int>(v);
}
__device__ inline int FloorPlusOneClamped(F v, int hi) {
  v = v > -1.0f ? v : -1.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  const int i = static_cast<int>(v);
  return min(i - (static_cast<F>(i) > v ? 1 : 0) + 1, hi);
}
__device__ inline int CeilPlusOneClamped(F v, int hi) {
  v = v > -1.0f ? v : -1.0f;
  v = v < static_cast<F>(hi) ? v : static_cast<F>(hi);
  const int i = static_cast<int>(v);
  return min(i + (static_cast<F>(i) < v ? 1 : 0) + 1, hi);
}

// The camera in float.
struct Camera {
  F r[9];
  F fx, fy, cx, cy, lim_x, lim_y;
  __device__ explicit Camera(const ProjectionInput& in)
      : fx(static_cast<F>(in.fx)), fy(static_cast<F>(in.fy)),
        cx(static_cast<F>(in.cx)), cy(static_cast<F>(in.cy)),
        lim_x(static_cast<F>(in.lim_x)), lim_y(static_cast<F>(in.lim_y)) {
    for (int i = 0; i < 9; ++i) r[i] = static_cast<F>(in.R[i]);
  }
};

// Gaussian n's inputs: camera-space mean and mean - camera center in
// double, then rounded, as the CPU gathers them.
struct Inputs {
  F p[3], v[3], q[4], log_scale[3], logit;
  __device__ Inputs(const ProjectionInput& in, int n) {
    const double* m = in.means + 3 * static_cast<size_t>(n);
    for (int r = 0; r < 3; ++r) {
      p[r] = static_cast<F>(in.R[3 * r] * m[0] + in.R[3 * r + 1] * m[1] +
                            in.R[3 * r + 2] * m[2] + in.t[r]);
      v[r] = static_cast<F>(m[r] - in.center[r]);
      log_scale[r] =
          static_cast<F>(in.log_scales[3 * static_cast<size_t>(n) + r]);
    }
    for (int c = 0; c < 4; ++c)
      q[c] = static_cast<F>(in.quats[4 * static_cast<size_t>(n) + c]);
    logit = static_cast<F>(in.opacity_logits[n]);
  }
};

struct Geometry {
  bool valid;  // in front of the near plane and not degenerate
  F q_unit[4], q_norm;
  F scale[3];
  F rot[9];
  F jw[6];
  F t[6];       // J R_cam R(q) diag(scale): cov2 = T T^T + dilation
  F a, b, c;    // dilated 2D covariance
  D conic[3];   // its inverse, in double
  F xz, yz;
  bool x_free, y_free;  // not clamped to the FOV
};

__device__ void ComputeGeometry(const Camera& cam, const Inputs& l,
                                Geometry* g) {
  const D dil = kCovarianceDilation;
  const F near_plane = static_cast<F>(kNearPlane);
  const F z = l.p[2];
  const F qn = sqrtf(l.q[0] * l.q[0] + l.q[1] * l.q[1] + l.q[2] * l.q[2] +
                     l.q[3] * l.q[3]);
  const F inv_qn = 1.0f / qn;
  const F w = l.q[0] * inv_qn, x = l.q[1] * inv_qn, y = l.q[2] * inv_qn,
          zq = l.q[3] * inv_qn;
  g->q_norm = qn;
  g->q_unit[0] = w;
  g->q_unit[1] = x;
  g->q_unit[2] = y;
  g->q_unit[3] = zq;
  F* rot = g->rot;
  rot[0] = 1 - 2 * (y * y + zq * zq);
  rot[1] = 2 * (x * y - w * zq);
  rot[2] = 2 * (x * zq + w * y);
  rot[3] = 2 * (x * y + w * zq);
  rot[4] = 1 - 2 * (x * x + zq * zq);
  rot[5] = 2 * (y * zq - w * x);
  rot[6] = 2 * (x * zq - w * y);
  rot[7] = 2 * (y * zq + w * x);
  rot[8] = 1 - 2 * (x * x + y * y);
  for (int k = 0; k < 3; ++k) g->scale[k] = Exp(l.log_scale[k]);
  const F raw_xz = l.p[0] / z, raw_yz = l.p[1] / z;
  g->x_free = !((raw_xz > 0 ? raw_xz : -raw_xz) > cam.lim_x);
  g->y_free = !((raw_yz > 0 ? raw_yz : -raw_yz) > cam.lim_y);
  g->xz = Min(Max(raw_xz, -cam.lim_x), cam.lim_x);
  g->yz = Min(Max(raw_yz, -cam.lim_y), cam.lim_y);
  const F jx = cam.fx / z, jy = cam.fy / z;
  for (int k = 0; k < 3; ++k) {
    g->jw[k] = jx * (cam.r[k] - g->xz * cam.r[6 + k]);
    g->jw[3 + k] = jy * (cam.r[3 + k] - g->yz * cam.r[6 + k]);
  }
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 3; ++k)
      g->t[3 * r + k] = (g->jw[3 * r] * rot[k] + g->jw[3 * r + 1] * rot[3 + k] +
                         g->jw[3 * r + 2] * rot[6 + k]) *
                        g->scale[k];
  D td[6];
  for (int k = 0; k < 6; ++k) td[k] = g->t[k];
  const D aa = td[0] * td[0] + td[1] * td[1] + td[2] * td[2];
  const D cc = td[3] * td[3] + td[4] * td[4] + td[5] * td[5];
  const D b = td[0] * td[3] + td[1] * td[4] + td[2] * td[5];
  const D c0 = td[1] * td[5] - td[2] * td[4];
  const D c1 = td[2] * td[3] - td[0] * td[5];
  const D c2 = td[0] * td[4] - td[1] * td[3];
  const D det = (c0 * c0 + c1 * c1 + c2 * c2) + dil * (aa + cc) + dil * dil;
  const D a = aa + dil, c = cc + dil;
  const D inv_det = 1.0 / det;
  g->a = static_cast<F>(a);
  g->b = static_cast<F>(b);
  g->c = static_cast<F>(c);
  g->conic[0] = c * inv_det;
  g->conic[1] = -b * inv_det;
  g->conic[2] = a * inv_det;
  g->valid = z > near_plane && qn > 0 && det > 0 && Finite(z) && Finite(qn) &&
             FiniteD(det) && FiniteD(g->conic[0]) && FiniteD(g->conic[1]) &&
             FiniteD(g->conic[2]);
}

// Unit view direction from the camera center; returns the distance.
__device__ F ViewDirection(const Inputs& l, F dir[3]) {
  const F d = sqrtf(l.v[0] * l.v[0] + l.v[1] * l.v[1] + l.v[2] * l.v[2]);
  const F inv = 1.0f / d;
  for (int k = 0; k < 3; ++k) dir[k] = l.v[k] * inv;
  return d;
}

// Real SH constants of 3DGS (core/model/sh.cc).
constexpr F kC0 = 0.28209479177387814f;
constexpr F kC1 = 0.4886025119029199f;
constexpr F kC20 = 1.0925484305920792f, kC21 = -1.0925484305920792f,
            kC22 = 0.31539156525252005f, kC23 = -1.0925484305920792f,
            kC24 = 0.5462742152960396f;
constexpr F kC30 = -0.5900435899266435f, kC31 = 2.890611442640554f,
            kC32 = -0.4570457994644658f, kC33 = 0.3731763325901154f,
            kC34 = -0.4570457994644658f, kC35 = 1.445305721320277f,
            kC36 = -0.5900435899266435f;

__device__ void ShBasis(const F dir[3], F basis[kMaxCoeffs]) {
  const F x = dir[0], y = dir[1], z = dir[2];
  const F xx = x * x, yy = y * y, zz = z * z;
  basis[0] = kC0;
  basis[1] = -kC1 * y;
  basis[2] = kC1 * z;
  basis[3] = -kC1 * x;
  basis[4] = kC20 * x * y;
  basis[5] = kC21 * y * z;
  basis[6] = kC22 * (2 * zz - xx - yy);
  basis[7] = kC23 * x * z;
  basis[8] = kC24 * (xx - yy);
  basis[9] = kC30 * y * (3 * xx - yy);
  basis[10] = kC31 * x * y * z;
  basis[11] = kC32 * y * (4 * zz - xx - yy);
  basis[12] = kC33 * z * (2 * zz - 3 * xx - 3 * yy);
  basis[13] = kC34 * x * (4 * zz - xx - yy);
  basis[14] = kC35 * z * (xx - yy);
  basis[15] = kC36 * x * (xx - 3 * yy);
}

// d loss / d dir from d loss / d basis (g past the degree's count is 0).
__device__ void ShBasisBackward(const F dir[3], const F g[kMaxCoeffs],
                                F d_dir[3]) {
  const F x = dir[0], y = dir[1], z = dir[2];
  const F xx = x * x, yy = y * y, zz = z * z;
  F dx = 0, dy = 0, dz = 0;
  dy += -kC1 * g[1];
  dz += kC1 * g[2];
  dx += -kC1 * g[3];
  dx += kC20 * y * g[4];
  dy += kC20 * x * g[4];
  dy += kC21 * z * g[5];
  dz += kC21 * y * g[5];
  dx += -2 * kC22 * x * g[6];
  dy += -2 * kC22 * y * g[6];
  dz += 4 * kC22 * z * g[6];
  dx += kC23 * z * g[7];
  dz += kC23 * x * g[7];
  dx += 2 * kC24 * x * g[8];
  dy += -2 * kC24 * y * g[8];
  dx += kC30 * 6 * x * y * g[9];
  dy += kC30 * (3 * xx - 3 * yy) * g[9];
  dx += kC31 * y * z * g[10];
  dy += kC31 * x * z * g[10];
  dz += kC31 * x * y * g[10];
  dx += kC32 * (-2 * x * y) * g[11];
  dy += kC32 * (4 * zz - xx - 3 * yy) * g[11];
  dz += kC32 * 8 * y * z * g[11];
  dx += kC33 * (-6 * x * z) * g[12];
  dy += kC33 * (-6 * y * z) * g[12];
  dz += kC33 * (6 * zz - 3 * xx - 3 * yy) * g[12];
  dx += kC34 * (4 * zz - 3 * xx - yy) * g[13];
  dy += kC34 * (-2 * x * y) * g[13];
  dz += kC34 * 8 * x * z * g[13];
  dx += kC35 * 2 * x * z * g[14];
  dy += kC35 * (-2 * y * z) * g[14];
  dz += kC35 * (xx - yy) * g[14];
  dx += kC36 * (3 * xx - 3 * yy) * g[15];
  dy += kC36 * (-6 * x * y) * g[15];
  d_dir[0] = dx;
  d_dir[1] = dy;
  d_dir[2] = dz;
}

// color[ch] = 0.5 + sum_k basis[k] sh[3k + ch] before the clamp at 0.
__device__ void ShColor(const ProjectionInput& in, int n, int coeffs,
                        const F basis[kMaxCoeffs], F color[3]) {
  const double* sh = in.sh + 3 * static_cast<size_t>(coeffs) * n;
  for (int ch = 0; ch < 3; ++ch) color[ch] = 0.5f;
  for (int k = 0; k < coeffs; ++k)
    for (int ch = 0; ch < 3; ++ch)
      color[ch] += basis[k] * static_cast<F>(sh[3 * k + ch]);
}

__global__ void ProjectKernel(ProjectionInput in, int count, int num_extra,
                              const double* extra,
                              ProjectedGaussian* projected, float* features,
                              int* tiles, int* visible) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const Camera cam(in);
  const Inputs l(in, n);
  Geometry g;
  ComputeGeometry(cam, l, &g);
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  F dir[3], basis[kMaxCoeffs], color[3];
  ViewDirection(l, dir);
  ShBasis(dir, basis);
  ShColor(in, n, coeffs, basis, color);

  const F min_alpha = static_cast<F>(kMinAlpha);
  const F tile = static_cast<F>(kTileSize);
  const F o = 1.0f / (1.0f + Exp(-l.logit));
  const F z = l.p[2];
  const F mx = cam.fx * l.p[0] / z + cam.cx;
  const F my = cam.fy * l.p[1] / z + cam.cy;
  const F half = 0.5f * (g.a - g.c);
  const F lambda = 0.5f * (g.a + g.c) + sqrtf(half * half + g.b * g.b);
  const F reach = 3.0f * sqrtf(lambda);
  const F capped = Min(reach, 1e9f);
  const int whole = static_cast<int>(capped);
  const F radius = static_cast<F>(whole + (static_cast<F>(whole) < capped));
  const F level = 2.0f * logf(Max(o / min_alpha, 1.0f));
  const F ex = sqrtf(level * g.a), ey = sqrtf(level * g.c);
  ProjectedGaussian p;
  p.px0 = FloorClamped(mx - ex - 0.5f, in.width);
  p.px1 = CeilPlusOneClamped(mx + ex - 0.5f, in.width);
  p.py0 = FloorClamped(my - ey - 0.5f, in.height);
  p.py1 = CeilPlusOneClamped(my + ey - 0.5f, in.height);
  const int tx0 = FloorClamped((mx - radius) / tile, in.tiles_x);
  const int tx1 = FloorPlusOneClamped((mx + radius) / tile, in.tiles_x);
  const int ty0 = FloorClamped((my - radius) / tile, in.tiles_y);
  const int ty1 = FloorPlusOneClamped((my + radius) / tile, in.tiles_y);
  p.tile_x0 = max(tx0, p.px0 / kTileSize);
  p.tile_y0 = max(ty0, p.py0 / kTileSize);
  p.tile_x1 = min(tx1, (p.px1 + kTileSize - 1) / kTileSize);
  p.tile_y1 = min(ty1, (p.py1 + kTileSize - 1) / kTileSize);
  const bool keep = g.valid && o >= min_alpha && Finite(mx) && Finite(my) &&
                    Finite(reach) && tx0 < tx1 && ty0 < ty1 &&
                    p.tile_x0 < p.tile_x1 && p.tile_y0 < p.tile_y1 &&
                    p.px0 < p.px1 && p.py0 < p.py1 && Finite(color[0]) &&
                    Finite(color[1]) && Finite(color[2]);
  p.mean[0] = mx;
  p.mean[1] = my;
  for (int k = 0; k < 3; ++k) p.conic[k] = static_cast<F>(g.conic[k]);
  p.opacity = o;
  p.depth = z;
  p.radius = keep ? static_cast<int>(radius) : 0;
  projected[n] = p;
  tiles[n] = keep ? (p.tile_x1 - p.tile_x0) * (p.tile_y1 - p.tile_y0) : 0;
  if (!keep) return;
  atomicAdd(visible, 1);
  const int nf = 4 + num_extra;
  float* f = features + static_cast<size_t>(nf) * n;
  for (int ch = 0; ch < 3; ++ch) f[ch] = Max(color[ch], 0.0f);
  f[3] = z;
  for (int e = 0; e < num_extra; ++e)
    f[4 + e] = static_cast<F>(extra[static_cast<size_t>(num_extra) * n + e]);
}

__global__ void ProjectBackwardKernel(ProjectionInput in, int count,
                                      int num_extra, const int* tiles,
                                      const double* grad2d,
                                      ProjectionGradients out,
                                      double* d_extra) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  const size_t un = static_cast<size_t>(n);
  double* g_sh = out.sh + 3 * static_cast<size_t>(coeffs) * un;
  if (tiles[n] == 0) {  // culled: zeros
    for (int k = 0; k < 3; ++k) out.means[3 * un + k] = 0;
    for (int k = 0; k < 3; ++k) out.log_scales[3 * un + k] = 0;
    for (int k = 0; k < 4; ++k) out.quats[4 * un + k] = 0;
    out.opacity_logits[n] = 0;
    for (int k = 0; k < 3 * coeffs; ++k) g_sh[k] = 0;
    for (int e = 0; e < num_extra; ++e) d_extra[num_extra * un + e] = 0;
    return;
  }
  const int stride = kTileGradHead + 4 + num_extra;
  const double* row = grad2d + static_cast<size_t>(stride) * un;
  for (int e = 0; e < num_extra; ++e)
    d_extra[num_extra * un + e] = row[kTileGradHead + 4 + e];
  const Camera cam(in);
  const Inputs l(in, n);
  Geometry g;
  ComputeGeometry(cam, l, &g);
  F pg[kTileGradHead + 4];
  for (int c = 0; c < kTileGradHead + 4; ++c) pg[c] = static_cast<F>(row[c]);

  const F z = l.p[2], x = l.p[0], y = l.p[1];
  // Conic -> dilated covariance, in double: dS = -C dC C.
  const D ca = g.conic[0], cb = g.conic[1], cc = g.conic[2];
  const D g0 = row[2], gh = 0.5 * row[3], g2 = row[4];
  const D m00 = ca * g0 + cb * gh, m01 = ca * gh + cb * g2;
  const D m10 = cb * g0 + cc * gh, m11 = cb * gh + cc * g2;
  const D s00 = -(m00 * ca + m01 * cb), s01 = -(m00 * cb + m01 * cc);
  const D s11 = -(m10 * cb + m11 * cc);
  // cov2 = T T^T + dilation: dT = 2 dS T; T = JW M, M = R(q) S.
  const F* rot = g.rot;
  const F* s = g.scale;
  F gt[6];
  for (int k = 0; k < 3; ++k) {
    const D t0 = g.t[k], t1 = g.t[3 + k];
    gt[k] = static_cast<F>(2 * (s00 * t0 + s01 * t1));
    gt[3 + k] = static_cast<F>(2 * (s01 * t0 + s11 * t1));
  }
  F g_jw[6];
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 3; ++k)
      g_jw[3 * r + k] = gt[3 * r] * rot[3 * k] * s[0] +
                        gt[3 * r + 1] * rot[3 * k + 1] * s[1] +
                        gt[3 * r + 2] * rot[3 * k + 2] * s[2];
  F g_m[9];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      g_m[3 * r + k] = g.jw[r] * gt[k] + g.jw[3 + r] * gt[3 + k];
  // d J = d JW R_cam^T: the entries J depends on.
  const auto g_j = [&](int row_j, int col) {
    return g_jw[3 * row_j] * cam.r[3 * col] +
           g_jw[3 * row_j + 1] * cam.r[3 * col + 1] +
           g_jw[3 * row_j + 2] * cam.r[3 * col + 2];
  };
  const F gj00 = g_j(0, 0), gj02 = g_j(0, 2), gj11 = g_j(1, 1),
          gj12 = g_j(1, 2);
  const F z2 = z * z, z3 = z2 * z;
  const F gm0 = pg[0], gm1 = pg[1];
  F gx = cam.fx / z * gm0;
  F gy = cam.fy / z * gm1;
  F gz = -(cam.fx * x * gm0 + cam.fy * y * gm1) / z2 + pg[kTileGradHead + 3];
  gz -= cam.fx / z2 * gj00 + cam.fy / z2 * gj11;
  // A coordinate clamped to the FOV passes no gradient to x or y.
  gx -= g.x_free ? cam.fx / z2 * gj02 : 0.0f;
  gz += g.x_free ? 2 * cam.fx * x / z3 * gj02 : cam.fx * g.xz / z2 * gj02;
  gy -= g.y_free ? cam.fy / z2 * gj12 : 0.0f;
  gz += g.y_free ? 2 * cam.fy * y / z3 * gj12 : cam.fy * g.yz / z2 * gj12;
  F g_mean[3];
  for (int k = 0; k < 3; ++k)
    g_mean[k] = cam.r[k] * gx + cam.r[3 + k] * gy + cam.r[6 + k] * gz;
  // M = R(q) diag(scale).
  F g_rot[9];
  for (int k = 0; k < 3; ++k) {
    F g_scale = 0;
    for (int r = 0; r < 3; ++r) {
      g_scale += g_m[3 * r + k] * rot[3 * r + k];
      g_rot[3 * r + k] = g_m[3 * r + k] * s[k];
    }
    out.log_scales[3 * un + k] = g_scale * s[k];
  }
  // The unit quaternion's gradient, then through the normalization.
  const F w = g.q_unit[0], qx = g.q_unit[1], qy = g.q_unit[2],
          qz = g.q_unit[3];
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
  const F inv_qn = 1.0f / g.q_norm;
  out.quats[4 * un + 0] = (d[0] - dot * w) * inv_qn;
  out.quats[4 * un + 1] = (d[1] - dot * qx) * inv_qn;
  out.quats[4 * un + 2] = (d[2] - dot * qy) * inv_qn;
  out.quats[4 * un + 3] = (d[3] - dot * qz) * inv_qn;
  // sigmoid' = e / (1 + e)^2 with e = exp(-logit).
  const F e = Exp(-l.logit);
  out.opacity_logits[n] = pg[5] * (e / ((1.0f + e) * (1.0f + e)));

  // Colour: SH + 0.5, clamped below at 0 (no gradient where clamped).
  F dir[3], basis[kMaxCoeffs], color[3];
  const F len = ViewDirection(l, dir);
  ShBasis(dir, basis);
  ShColor(in, n, coeffs, basis, color);
  F g_color[3];
  for (int ch = 0; ch < 3; ++ch)
    g_color[ch] = color[ch] < 0 ? 0.0f : pg[kTileGradHead + ch];
  const double* sh = in.sh + 3 * static_cast<size_t>(coeffs) * un;
  F g_basis[kMaxCoeffs];
  for (int k = 0; k < kMaxCoeffs; ++k) g_basis[k] = 0.0f;
  for (int k = 0; k < coeffs; ++k) {
    g_basis[k] = static_cast<F>(sh[3 * k]) * g_color[0] +
                 static_cast<F>(sh[3 * k + 1]) * g_color[1] +
                 static_cast<F>(sh[3 * k + 2]) * g_color[2];
    for (int ch = 0; ch < 3; ++ch) g_sh[3 * k + ch] = basis[k] * g_color[ch];
  }
  if (in.sh_degree > 0) {
    F g_dir[3];
    ShBasisBackward(dir, g_basis, g_dir);
    const F dot_dir =
        g_dir[0] * dir[0] + g_dir[1] * dir[1] + g_dir[2] * dir[2];
    const F inv_len = 1.0f / len;
    for (int k = 0; k < 3; ++k)
      g_mean[k] += (g_dir[k] - dot_dir * dir[k]) * inv_len;
  }
  for (int k = 0; k < 3; ++k) out.means[3 * un + k] = g_mean[k];
}

int Blocks(int count) { return (count + kThreads - 1) / kThreads; }

}  // namespace

void ProjectForward(const ProjectionInput& in, int count, int num_extra,
                    const double* extra, ProjectedGaussian* projected,
                    float* features, int* tiles, int* visible) {
  ES_CUDA_CHECK(cudaMemset(visible, 0, sizeof(int)));
  if (count == 0) return;
  ProjectKernel<<<Blocks(count), kThreads>>>(in, count, num_extra, extra,
                                             projected, features, tiles,
                                             visible);
  ES_CUDA_CHECK_LAUNCH("ProjectKernel");
}

void ProjectBackward(const ProjectionInput& in, int count, int num_extra,
                     const int* tiles, const double* grad2d,
                     const ProjectionGradients& out, double* d_extra) {
  if (count == 0) return;
  ProjectBackwardKernel<<<Blocks(count), kThreads>>>(in, count, num_extra,
                                                     tiles, grad2d, out,
                                                     d_extra);
  ES_CUDA_CHECK_LAUNCH("ProjectBackwardKernel");
}

}  // namespace cuda
}  // namespace es
