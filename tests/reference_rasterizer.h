#ifndef EULERSPLAT_TESTS_REFERENCE_RASTERIZER_H_
#define EULERSPLAT_TESTS_REFERENCE_RASTERIZER_H_

// A slow, obviously-correct twin of core/rasterizer (as gsplat keeps one in
// torch): every pixel walks every Gaussian in depth order, written straight
// from the 3DGS equations with no tiling tricks, templated on the scalar so
// ceres::Jet gives its exact gradients. Tests only.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <ceres/jet.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "tests/raster_test_scene.h"

namespace es {
namespace reference {

inline double Val(double x) { return x; }
template <int N>
double Val(const ceres::Jet<double, N>& x) {
  return x.a;
}

template <typename T>
struct Images {
  std::vector<T> rgb, alpha, depth, extra;
};

// The 3DGS real SH basis, written out independently of core/sh.cc.
template <typename T>
void ShBasis(int degree, T x, T y, T z, T* b) {
  b[0] = T(0.28209479177387814);
  if (degree < 1) return;
  const double c1 = 0.4886025119029199;
  b[1] = -c1 * y;
  b[2] = c1 * z;
  b[3] = -c1 * x;
  if (degree < 2) return;
  b[4] = 1.0925484305920792 * x * y;
  b[5] = -1.0925484305920792 * y * z;
  b[6] = 0.31539156525252005 * (2.0 * z * z - x * x - y * y);
  b[7] = -1.0925484305920792 * x * z;
  b[8] = 0.5462742152960396 * (x * x - y * y);
  if (degree < 3) return;
  b[9] = -0.5900435899266435 * y * (3.0 * x * x - y * y);
  b[10] = 2.890611442640554 * x * y * z;
  b[11] = -0.4570457994644658 * y * (4.0 * z * z - x * x - y * y);
  b[12] = 0.3731763325901154 * z * (2.0 * z * z - 3.0 * x * x - 3.0 * y * y);
  b[13] = -0.4570457994644658 * x * (4.0 * z * z - x * x - y * y);
  b[14] = 1.445305721320277 * z * (x * x - y * y);
  b[15] = -0.5900435899266435 * x * (x * x - 3.0 * y * y);
}

template <typename T>
Images<T> Render(const Camera& cam, const Splats<T>& s,
                 const Eigen::Vector3d& background) {
  using std::exp;
  using std::sqrt;
  const int w = cam.width, h = cam.height, ne = s.num_extra;
  const Eigen::Matrix3d r = cam.R();
  const Eigen::Vector3d center = cam.Center();
  const double lim_x = 1.3 * 0.5 * w / cam.fx, lim_y = 1.3 * 0.5 * h / cam.fy;
  const int k_count = NumShCoeffs(s.sh_degree);

  struct Projected {
    int index;
    double depth;
    T u, v, ca, cb, cc, opacity, z, color[3];
    int tx0, tx1, ty0, ty1;  // inclusive tile range
  };
  std::vector<Projected> list;
  for (int n = 0; n < s.count; ++n) {
    const T* p = &s.means[3 * n];
    T pc[3];
    for (int i = 0; i < 3; ++i) {
      pc[i] = r(i, 0) * p[0] + r(i, 1) * p[1] + r(i, 2) * p[2] + cam.t_cw[i];
    }
    if (!(Val(pc[2]) > kNearPlane)) continue;
    const T* q = &s.quats[4 * n];
    const T qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const T qw = q[0] / qn, qx = q[1] / qn, qy = q[2] / qn, qz = q[3] / qn;
    const T rot[3][3] = {
        {1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy - qw * qz),
         2.0 * (qx * qz + qw * qy)},
        {2.0 * (qx * qy + qw * qz), 1.0 - 2.0 * (qx * qx + qz * qz),
         2.0 * (qy * qz - qw * qx)},
        {2.0 * (qx * qz - qw * qy), 2.0 * (qy * qz + qw * qx),
         1.0 - 2.0 * (qx * qx + qy * qy)}};
    T sig[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        sig[i][j] = T(0);
        for (int k = 0; k < 3; ++k) {
          const T sk = exp(s.log_scales[3 * n + k]);
          sig[i][j] += rot[i][k] * sk * sk * rot[j][k];
        }
      }
    }
    const T z = pc[2];
    T xz = pc[0] / z, yz = pc[1] / z;
    if (Val(xz) > lim_x) xz = T(lim_x);
    if (Val(xz) < -lim_x) xz = T(-lim_x);
    if (Val(yz) > lim_y) yz = T(lim_y);
    if (Val(yz) < -lim_y) yz = T(-lim_y);
    const T jac[2][3] = {{cam.fx / z, T(0), -cam.fx * xz / z},
                         {T(0), cam.fy / z, -cam.fy * yz / z}};
    T jw[2][3];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 3; ++j) {
        jw[i][j] = jac[i][0] * r(0, j) + jac[i][1] * r(1, j) +
                   jac[i][2] * r(2, j);
      }
    }
    T cov[2][2];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) {
        cov[i][j] = T(0);
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) {
            cov[i][j] += jw[i][a] * sig[a][b] * jw[j][b];
          }
        }
      }
    }
    cov[0][0] += kCovarianceDilation;
    cov[1][1] += kCovarianceDilation;
    const T det = cov[0][0] * cov[1][1] - cov[0][1] * cov[1][0];
    if (!(Val(det) > 0)) continue;
    Projected pr;
    pr.index = n;
    pr.depth = Val(z);
    pr.z = z;
    pr.ca = cov[1][1] / det;
    pr.cb = -cov[0][1] / det;
    pr.cc = cov[0][0] / det;
    pr.u = cam.fx * pc[0] / z + cam.cx;
    pr.v = cam.fy * pc[1] / z + cam.cy;
    const double mid = 0.5 * (Val(cov[0][0]) + Val(cov[1][1]));
    const double lambda =
        mid + std::sqrt(std::max(0.0, mid * mid - Val(det)));
    const double radius = std::ceil(3 * std::sqrt(lambda));
    const int tiles_x = (w + kTileSize - 1) / kTileSize;
    const int tiles_y = (h + kTileSize - 1) / kTileSize;
    pr.tx0 = std::max(0.0, std::floor((Val(pr.u) - radius) / kTileSize));
    pr.tx1 = std::min(tiles_x - 1.0,
                      std::floor((Val(pr.u) + radius) / kTileSize));
    pr.ty0 = std::max(0.0, std::floor((Val(pr.v) - radius) / kTileSize));
    pr.ty1 = std::min(tiles_y - 1.0,
                      std::floor((Val(pr.v) + radius) / kTileSize));
    if (pr.tx0 > pr.tx1 || pr.ty0 > pr.ty1) continue;
    pr.opacity = 1.0 / (1.0 + exp(-s.opacity_logits[n]));
    if (Val(pr.opacity) < kMinAlpha) continue;
    T d[3];
    for (int i = 0; i < 3; ++i) d[i] = p[i] - center[i];
    const T len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    T basis[16];
    ShBasis(s.sh_degree, d[0] / len, d[1] / len, d[2] / len, basis);
    for (int c = 0; c < 3; ++c) {
      T v = T(0.5);
      for (int k = 0; k < k_count; ++k) {
        v += basis[k] * s.sh[(n * k_count + k) * 3 + c];
      }
      pr.color[c] = Val(v) < 0 ? T(0) : v;
    }
    list.push_back(pr);
  }
  std::sort(list.begin(), list.end(),
            [](const Projected& a, const Projected& b) {
              return a.depth < b.depth ||
                     (a.depth == b.depth && a.index < b.index);
            });

  Images<T> out;
  out.rgb.assign(3 * w * h, T(0));
  out.alpha.assign(w * h, T(0));
  out.depth.assign(w * h, T(0));
  out.extra.assign(w * h * ne, T(0));
  for (int i = 0; i < h; ++i) {
    for (int j = 0; j < w; ++j) {
      const int pix = i * w + j, tx = j / kTileSize, ty = i / kTileSize;
      T trans(1);
      for (const Projected& g : list) {
        if (tx < g.tx0 || tx > g.tx1 || ty < g.ty0 || ty > g.ty1) continue;
        const T dx = j + 0.5 - g.u, dy = i + 0.5 - g.v;
        const T sigma =
            0.5 * (g.ca * dx * dx + g.cc * dy * dy) + g.cb * dx * dy;
        if (Val(sigma) < 0) continue;
        T alpha = g.opacity * exp(-sigma);
        if (Val(alpha) > kMaxAlpha) alpha = T(kMaxAlpha);
        if (Val(alpha) < kMinAlpha) continue;
        const T next = trans * (1.0 - alpha);
        if (Val(next) < kMinTransmittance) break;
        const T weight = alpha * trans;
        for (int c = 0; c < 3; ++c) out.rgb[3 * pix + c] += weight * g.color[c];
        out.depth[pix] += weight * g.z;
        for (int e = 0; e < ne; ++e) {
          out.extra[pix * ne + e] += weight * s.extra[g.index * ne + e];
        }
        trans = next;
      }
      for (int c = 0; c < 3; ++c) out.rgb[3 * pix + c] += background[c] * trans;
      out.alpha[pix] = 1.0 - trans;
    }
  }
  return out;
}


}  // namespace reference
}  // namespace es

#endif  // EULERSPLAT_TESTS_REFERENCE_RASTERIZER_H_
