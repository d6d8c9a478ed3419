#include "core/render/raster_project.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <glog/logging.h>

#include "core/model/sh.h"
#include "core/render/raster_constants.h"

namespace es {
namespace {

using Eigen::Matrix2d;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

// 3DGS clamps x/z and y/z to 1.3 tan(fov / 2) in the projection Jacobian so
// Gaussians far outside the view do not get huge, unstable footprints.
constexpr double kFovClampFactor = 1.3;

Matrix3d QuatToRotation(double w, double x, double y, double z) {
  Matrix3d r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return r;
}

// d loss / d (w, x, y, z) of a unit quaternion from d loss / d R.
Eigen::Vector4d RotationBackward(const double q[4], const Matrix3d& g) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Vector4d d;
  d[0] = 2 * (-z * g(0, 1) + y * g(0, 2) + z * g(1, 0) - x * g(1, 2) -
              y * g(2, 0) + x * g(2, 1));
  d[1] = 2 * (y * g(0, 1) + z * g(0, 2) + y * g(1, 0) - 2 * x * g(1, 1) -
              w * g(1, 2) + z * g(2, 0) + w * g(2, 1) - 2 * x * g(2, 2));
  d[2] = 2 * (-2 * y * g(0, 0) + x * g(0, 1) + w * g(0, 2) + x * g(1, 0) +
              z * g(1, 2) - w * g(2, 0) + z * g(2, 1) - 2 * y * g(2, 2));
  d[3] = 2 * (-2 * z * g(0, 0) - w * g(0, 1) + x * g(0, 2) + w * g(1, 0) -
              2 * z * g(1, 1) + y * g(1, 2) + x * g(2, 0) + y * g(2, 1));
  return d;
}

// Intermediates of the projection shared by forward and backward.
struct Geometry {
  Vector3d p_cam;
  double q_unit[4], q_norm;
  Vector3d scale;
  Matrix3d rot;   // from q_unit
  Matrix3d m;     // rot * diag(scale)
  Matrix3d cov3;  // m m^T
  bool x_clamped, y_clamped;
  double xz, yz;  // clamped x/z, y/z used in the Jacobian
  Mat23 jw;       // J * R_cam
  Matrix2d cov2;  // dilated
  Matrix2d conic;
  double det;
};

// Returns false when the Gaussian is behind the near plane or degenerate.
bool ComputeGeometry(const ProjectionCamera& cam, const SplatView& s, int n,
                     Geometry* g) {
  const Vector3d p(s.means[3 * n], s.means[3 * n + 1], s.means[3 * n + 2]);
  g->p_cam = cam.R * p + cam.t;
  const double z = g->p_cam.z();
  if (!(z > kNearPlane) || !std::isfinite(z)) return false;
  const double* q = s.quats + 4 * n;
  g->q_norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(g->q_norm > 0) || !std::isfinite(g->q_norm)) return false;
  for (int i = 0; i < 4; ++i) g->q_unit[i] = q[i] / g->q_norm;
  for (int i = 0; i < 3; ++i) g->scale[i] = std::exp(s.log_scales[3 * n + i]);
  g->rot = QuatToRotation(g->q_unit[0], g->q_unit[1], g->q_unit[2],
                          g->q_unit[3]);
  g->m = g->rot * g->scale.asDiagonal();
  g->cov3 = g->m * g->m.transpose();

  const double raw_xz = g->p_cam.x() / z, raw_yz = g->p_cam.y() / z;
  g->x_clamped = std::abs(raw_xz) > cam.lim_x;
  g->y_clamped = std::abs(raw_yz) > cam.lim_y;
  g->xz = std::clamp(raw_xz, -cam.lim_x, cam.lim_x);
  g->yz = std::clamp(raw_yz, -cam.lim_y, cam.lim_y);
  Mat23 j;
  j << cam.fx / z, 0, -cam.fx * g->xz / z, 0, cam.fy / z, -cam.fy * g->yz / z;
  g->jw = j * cam.R;
  g->cov2 = g->jw * g->cov3 * g->jw.transpose();
  g->cov2(0, 0) += kCovarianceDilation;
  g->cov2(1, 1) += kCovarianceDilation;
  g->det = g->cov2(0, 0) * g->cov2(1, 1) - g->cov2(0, 1) * g->cov2(1, 0);
  if (!(g->det > 0) || !std::isfinite(g->det)) return false;
  g->conic << g->cov2(1, 1) / g->det, -g->cov2(0, 1) / g->det,
      -g->cov2(1, 0) / g->det, g->cov2(0, 0) / g->det;
  return g->conic.allFinite();
}

// View direction from the camera center to the mean, and its length.
double ViewDirection(const ProjectionCamera& cam, const SplatView& s, int n,
                     double dir[3]) {
  Vector3d v(s.means[3 * n] - cam.center.x(),
             s.means[3 * n + 1] - cam.center.y(),
             s.means[3 * n + 2] - cam.center.z());
  const double len = v.norm();
  for (int i = 0; i < 3; ++i) dir[i] = v[i] / len;
  return len;
}

// Clamps a floating tile or pixel bound into [lo, hi] before the int cast.
int ClampToInt(double v, int lo, int hi) {
  if (!(v > lo)) return lo;  // also NaN
  if (v > hi) return hi;
  return static_cast<int>(v);
}

}  // namespace

ProjectionCamera::ProjectionCamera(const Camera& camera)
    : R(camera.R()),
      t(camera.t_cw),
      center(camera.Center()),
      fx(camera.fx),
      fy(camera.fy),
      cx(camera.cx),
      cy(camera.cy),
      lim_x(kFovClampFactor * 0.5 * camera.width / camera.fx),
      lim_y(kFovClampFactor * 0.5 * camera.height / camera.fy),
      width(camera.width),
      height(camera.height),
      tiles_x((camera.width + kTileSize - 1) / kTileSize),
      tiles_y((camera.height + kTileSize - 1) / kTileSize) {}

bool ProjectSplat(const ProjectionCamera& cam, const SplatView& s, int n,
                  ProjectedSplat* out) {
  const double opacity = Sigmoid(s.opacity_logits[n]);
  // alpha = min(0.99, o * G) <= o, so such a Gaussian never shows.
  if (!(opacity >= kMinAlpha)) return false;
  Geometry g;
  if (!ComputeGeometry(cam, s, n, &g)) return false;
  const double z = g.p_cam.z();
  const double mx = cam.fx * g.p_cam.x() / z + cam.cx;
  const double my = cam.fy * g.p_cam.y() / z + cam.cy;
  const double a = g.cov2(0, 0), c = g.cov2(1, 1);
  const double mid = 0.5 * (a + c);
  const double lambda = mid + std::sqrt(std::max(0.0, mid * mid - g.det));
  const double radius = std::ceil(3 * std::sqrt(lambda));
  if (!std::isfinite(mx) || !std::isfinite(my) || !std::isfinite(radius)) {
    return false;
  }
  // Pixels where o * exp(-sigma) >= kMinAlpha lie in the ellipse
  // sigma <= log(o / kMinAlpha), whose bounding box has half-widths
  // sqrt(2 log(o / kMinAlpha) cov_xx) and likewise in y.
  const double level = 2 * std::log(opacity / kMinAlpha);
  const double ex = std::sqrt(level * a), ey = std::sqrt(level * c);
  // Pixel j's center j + 0.5 lies in [mx - ex, mx + ex]; one pixel margin.
  out->px0 = ClampToInt(std::floor(mx - ex - 0.5), 0, cam.width);
  out->px1 = ClampToInt(std::ceil(mx + ex - 0.5) + 1, 0, cam.width);
  out->py0 = ClampToInt(std::floor(my - ey - 0.5), 0, cam.height);
  out->py1 = ClampToInt(std::ceil(my + ey - 0.5) + 1, 0, cam.height);
  // Tiles touched by the 3-sigma square [m - r, m + r].
  const int tx0 = ClampToInt(std::floor((mx - radius) / kTileSize), 0,
                             cam.tiles_x);
  const int tx1 = ClampToInt(std::floor((mx + radius) / kTileSize) + 1, 0,
                             cam.tiles_x);
  const int ty0 = ClampToInt(std::floor((my - radius) / kTileSize), 0,
                             cam.tiles_y);
  const int ty1 = ClampToInt(std::floor((my + radius) / kTileSize) + 1, 0,
                             cam.tiles_y);
  if (tx0 >= tx1 || ty0 >= ty1) return false;  // off-screen
  out->tile_x0 = std::max(tx0, out->px0 / kTileSize);
  out->tile_y0 = std::max(ty0, out->py0 / kTileSize);
  out->tile_x1 = std::min(tx1, (out->px1 + kTileSize - 1) / kTileSize);
  out->tile_y1 = std::min(ty1, (out->py1 + kTileSize - 1) / kTileSize);
  if (out->tile_x0 >= out->tile_x1 || out->tile_y0 >= out->tile_y1 ||
      out->px0 >= out->px1 || out->py0 >= out->py1) {
    return false;
  }

  double dir[3], basis[16];
  ViewDirection(cam, s, n, dir);
  EvalShBasis(s.sh_degree, dir, basis);
  const int k_count = NumShCoeffs(s.sh_degree);
  const double* sh = s.sh + 3 * k_count * n;
  for (int ch = 0; ch < 3; ++ch) {
    double v = 0.5;
    for (int k = 0; k < k_count; ++k) v += basis[k] * sh[3 * k + ch];
    if (!std::isfinite(v)) return false;
    out->color[ch] = std::max(v, 0.0);
  }
  out->mean2d[0] = mx;
  out->mean2d[1] = my;
  out->conic[0] = g.conic(0, 0);
  out->conic[1] = g.conic(0, 1);
  out->conic[2] = g.conic(1, 1);
  out->depth = z;
  out->opacity = opacity;
  out->radius = static_cast<int>(std::min(radius, 1e9));
  return true;
}

void ProjectSplatBackward(const ProjectionCamera& cam, const SplatView& s,
                          int n, const ProjectedGradient& pg,
                          SplatGradients* grads) {
  Geometry g;
  const bool visible = ComputeGeometry(cam, s, n, &g);
  CHECK(visible) << "backward through a culled Gaussian " << n;
  const double z = g.p_cam.z(), x = g.p_cam.x(), y = g.p_cam.y();

  // Conic -> dilated 2D covariance: dC = -C dS C.
  Matrix2d g_conic;
  g_conic << pg.conic[0], 0.5 * pg.conic[1], 0.5 * pg.conic[1], pg.conic[2];
  const Matrix2d g_cov2 = -g.conic * g_conic * g.conic;
  // cov2 = JW cov3 (JW)^T + dilation.
  const Mat23 g_jw = 2 * g_cov2 * g.jw * g.cov3;
  const Matrix3d g_cov3 = g.jw.transpose() * g_cov2 * g.jw;
  const Mat23 g_j = g_jw * cam.R.transpose();

  Vector3d g_pcam(0, 0, 0);
  // Mean2d.
  g_pcam.x() += cam.fx / z * pg.mean2d[0];
  g_pcam.y() += cam.fy / z * pg.mean2d[1];
  g_pcam.z() -= (cam.fx * x * pg.mean2d[0] + cam.fy * y * pg.mean2d[1]) /
                (z * z);
  g_pcam.z() += pg.depth;
  // Jacobian J(x, y, z); a clamped coordinate passes no gradient to x or y.
  const double z2 = z * z;
  g_pcam.z() -= cam.fx / z2 * g_j(0, 0) + cam.fy / z2 * g_j(1, 1);
  if (g.x_clamped) {
    g_pcam.z() += cam.fx * g.xz / z2 * g_j(0, 2);
  } else {
    g_pcam.x() -= cam.fx / z2 * g_j(0, 2);
    g_pcam.z() += 2 * cam.fx * x / (z2 * z) * g_j(0, 2);
  }
  if (g.y_clamped) {
    g_pcam.z() += cam.fy * g.yz / z2 * g_j(1, 2);
  } else {
    g_pcam.y() -= cam.fy / z2 * g_j(1, 2);
    g_pcam.z() += 2 * cam.fy * y / (z2 * z) * g_j(1, 2);
  }
  Vector3d g_mean = cam.R.transpose() * g_pcam;

  // Color: SH + 0.5 clamped below at 0.
  double dir[3], basis[16];
  const double len = ViewDirection(cam, s, n, dir);
  EvalShBasis(s.sh_degree, dir, basis);
  const int k_count = NumShCoeffs(s.sh_degree);
  const double* sh = s.sh + 3 * k_count * n;
  double* g_sh = grads->sh.data() + 3 * k_count * n;
  double g_color[3];
  for (int ch = 0; ch < 3; ++ch) {
    double v = 0.5;
    for (int k = 0; k < k_count; ++k) v += basis[k] * sh[3 * k + ch];
    g_color[ch] = v < 0 ? 0.0 : pg.color[ch];
  }
  double g_basis[16];
  for (int k = 0; k < k_count; ++k) {
    g_basis[k] = 0;
    for (int ch = 0; ch < 3; ++ch) {
      g_sh[3 * k + ch] = basis[k] * g_color[ch];
      g_basis[k] += sh[3 * k + ch] * g_color[ch];
    }
  }
  if (s.sh_degree > 0) {
    double g_dir[3];
    ShBasisBackward(s.sh_degree, dir, g_basis, g_dir);
    const double dot =
        g_dir[0] * dir[0] + g_dir[1] * dir[1] + g_dir[2] * dir[2];
    for (int i = 0; i < 3; ++i) g_mean[i] += (g_dir[i] - dot * dir[i]) / len;
  }
  for (int i = 0; i < 3; ++i) grads->means[3 * n + i] = g_mean[i];

  // cov3 = M M^T, M = R(q) diag(scale).
  const Matrix3d g_m = 2 * g_cov3 * g.m;
  Matrix3d g_rot;
  for (int j = 0; j < 3; ++j) {
    double g_scale = 0;
    for (int i = 0; i < 3; ++i) {
      g_scale += g_m(i, j) * g.rot(i, j);
      g_rot(i, j) = g_m(i, j) * g.scale[j];
    }
    grads->log_scales[3 * n + j] = g_scale * g.scale[j];
  }
  const Eigen::Vector4d g_qu = RotationBackward(g.q_unit, g_rot);
  double dot = 0;
  for (int i = 0; i < 4; ++i) dot += g_qu[i] * g.q_unit[i];
  for (int i = 0; i < 4; ++i) {
    grads->quats[4 * n + i] = (g_qu[i] - dot * g.q_unit[i]) / g.q_norm;
  }
  const double o = Sigmoid(s.opacity_logits[n]);
  grads->opacity_logits[n] = pg.opacity * o * (1 - o);
}

ProjectionInput MakeProjectionInput(const ProjectionCamera& cam,
                                    const SplatView& s) {
  ProjectionInput in;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) in.R[3 * r + c] = cam.R(r, c);
    in.t[r] = cam.t[r];
    in.center[r] = cam.center[r];
  }
  in.fx = cam.fx;
  in.fy = cam.fy;
  in.cx = cam.cx;
  in.cy = cam.cy;
  in.lim_x = cam.lim_x;
  in.lim_y = cam.lim_y;
  in.width = cam.width;
  in.height = cam.height;
  in.tiles_x = cam.tiles_x;
  in.tiles_y = cam.tiles_y;
  in.sh_degree = s.sh_degree;
  in.means = s.means;
  in.log_scales = s.log_scales;
  in.quats = s.quats;
  in.opacity_logits = s.opacity_logits;
  in.sh = s.sh;
  return in;
}

ProjectionGradients MakeProjectionGradients(SplatGradients* grads) {
  return {grads->means.data(), grads->log_scales.data(),
          grads->quats.data(), grads->opacity_logits.data(),
          grads->sh.data()};
}

}  // namespace es
