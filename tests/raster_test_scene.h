#ifndef EULERSPLAT_TESTS_RASTER_TEST_SCENE_H_
#define EULERSPLAT_TESTS_RASTER_TEST_SCENE_H_

// The small scenes the rasterizer tests render (the CPU rasterizer against
// its reference twin, the CUDA rasterizer against the CPU one): a camera
// and double splat arrays, with the hard cases (needles, huge and
// near-plane Gaussians, off-screen ones, opaque stacks, tile corners).
// Tests only; nothing here needs more than Eigen.

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/render/raster_constants.h"
#include "core/render/rasterizer.h"

namespace es {
namespace reference {

// The background the rasterizer tests render on: neither black nor white,
// so a wrong blend with it shows.
inline const Eigen::Vector3d kTestBackground(0.3, 0.6, 0.1);

// Render options on kTestBackground, in double or (the default) float.
inline RenderOptions TestRenderOptions(bool use_double = false) {
  RenderOptions o;
  o.use_double = use_double;
  o.background = kTestBackground;
  return o;
}

// Splat attributes in the SplatView layouts, in scalar type T.
template <typename T>
struct Splats {
  int count = 0, sh_degree = 0, num_extra = 0;
  std::vector<T> means, log_scales, quats, opacity_logits, sh, extra;
};

// A small scene for the rasterizer tests: camera and double splat arrays.
struct TestScene {
  Camera camera;
  int count = 0, sh_degree = 0, num_extra = 0;
  std::vector<double> means, log_scales, quats, opacity_logits, sh, extra;

  SplatView View() const {
    SplatView v;
    v.count = count;
    v.sh_degree = sh_degree;
    v.means = means.data();
    v.log_scales = log_scales.data();
    v.quats = quats.data();
    v.opacity_logits = opacity_logits.data();
    v.sh = sh.data();
    v.num_extra = num_extra;
    v.extra = extra.data();
    return v;
  }
  template <typename T>
  Splats<T> As() const {
    Splats<T> s;
    s.count = count;
    s.sh_degree = sh_degree;
    s.num_extra = num_extra;
    auto copy = [](const std::vector<double>& v) {
      return std::vector<T>(v.begin(), v.end());
    };
    s.means = copy(means);
    s.log_scales = copy(log_scales);
    s.quats = copy(quats);
    s.opacity_logits = copy(opacity_logits);
    s.sh = copy(sh);
    s.extra = copy(extra);
    return s;
  }
  // Adds a Gaussian given in camera coordinates; SH and extras random later.
  void Add(const Eigen::Vector3d& p_cam, const Eigen::Vector3d& scale,
           const Eigen::Vector4d& quat, double opacity_logit) {
    const Eigen::Vector3d p =
        camera.R().transpose() * (p_cam - camera.t_cw);
    for (int i = 0; i < 3; ++i) {
      means.push_back(p[i]);
      log_scales.push_back(std::log(scale[i]));
    }
    for (int i = 0; i < 4; ++i) quats.push_back(quat[i]);
    opacity_logits.push_back(opacity_logit);
    sh.resize(sh.size() + 3 * NumShCoeffs(sh_degree), 0.0);
    extra.resize(extra.size() + num_extra, 0.0);
    ++count;
  }
};

// A w x h camera with a slightly off-center principal point and a generic
// pose, so the tests exercise the rotation and translation.
inline Camera TestCamera(int w, int h) {
  Camera c;
  c.width = w;
  c.height = h;
  c.fx = 1.1 * w;
  c.fy = 1.05 * w;
  c.cx = 0.48 * w;
  c.cy = 0.53 * h;
  c.q_cw = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(
                                  1, -2, 0.5).normalized()));
  c.t_cw = Eigen::Vector3d(0.2, -0.4, 0.7);
  return c;
}

// Random Gaussians of varied kinds in front of the camera: ordinary ones of
// a few pixels, thin needles, large blobs, ones near the near plane, ones
// partly off-screen or beyond the FOV clamp, some opaque enough to hit the
// 0.99 alpha clamp. Deterministic for a seed.
inline TestScene RandomScene(unsigned seed, int count, int sh_degree,
                             int num_extra, int w = 48, int h = 40) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto range = [&](double a, double b) { return a + (b - a) * uni(rng); };
  TestScene s;
  s.camera = TestCamera(w, h);
  s.sh_degree = sh_degree;
  s.num_extra = num_extra;
  const double f = s.camera.fx;
  for (int i = 0; i < count; ++i) {
    const int kind = i % 6;
    double z = range(2, 6);
    double u = range(0, w), v = range(0, h);
    double px = range(1, 6);  // footprint sigma in pixels
    Eigen::Vector3d scale;
    if (kind == 1) {  // needle
      scale << px * z / f * 0.02, px * z / f * 0.02, px * z / f * 3;
    } else if (kind == 2) {  // large blob
      px = range(20, 60);
      scale = Eigen::Vector3d::Constant(px * z / f);
    } else if (kind == 3) {  // near the near plane
      z = range(0.05, 0.3);
      scale = Eigen::Vector3d::Constant(range(0.002, 0.01));
    } else if (kind == 4) {  // partly off-screen, maybe past the FOV clamp
      u = uni(rng) < 0.5 ? range(-0.4 * w, 0) : range(w, 1.4 * w);
      px = range(5, 15);
      scale = Eigen::Vector3d::Constant(px * z / f);
    } else {
      for (int k = 0; k < 3; ++k) scale[k] = px * z / f * range(0.4, 1.5);
    }
    const Eigen::Vector3d p_cam = s.camera.Unproject(u, v, z);
    Eigen::Vector4d q(normal(rng), normal(rng), normal(rng), normal(rng));
    q *= range(0.5, 2.0) / q.norm();
    const double logit = kind == 5 ? range(5, 7) : range(-2, 3);
    s.Add(p_cam, scale, q, logit);
  }
  const int k_count = NumShCoeffs(sh_degree);
  for (int n = 0; n < count; ++n) {
    for (int k = 0; k < k_count; ++k) {
      for (int c = 0; c < 3; ++c) {
        s.sh[(n * k_count + k) * 3 + c] = range(-1, 1) * (k == 0 ? 1.5 : 0.4);
      }
    }
    for (int e = 0; e < num_extra; ++e) s.extra[n * num_extra + e] = uni(rng);
  }
  return s;
}

// A scene with a stack of opaque Gaussians at the center, so transmittance
// runs out, plus the usual random mix.
inline TestScene StackedScene(unsigned seed, int degree) {
  TestScene s = RandomScene(seed, 14, degree, 1);
  const Eigen::Vector3d dir = s.camera.Unproject(20, 22, 1.0);
  for (int k = 0; k < 8; ++k) {
    s.Add(dir * (3 + 0.5 * k), Eigen::Vector3d(0.3, 0.2, 0.25),
          Eigen::Vector4d(1, 0.1 * k, 0, 0), 2.5 + 0.3 * k);
    const int n = s.count - 1, kc = NumShCoeffs(degree);
    for (int c = 0; c < 3; ++c) s.sh[n * kc * 3 + c] = 0.5 * (c - k % 3);
  }
  return s;
}

// Needles at many angles across tile borders, and round footprints
// centred on tile corners: most rows of their pixel boxes within a tile
// miss the ellipse, rows the CPU tile passes skip (RowReached).
inline TestScene NeedleScene() {
  TestScene s;
  s.camera = TestCamera(64, 48);
  s.sh_degree = 0;
  s.num_extra = 1;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double f = s.camera.fx;
  const Eigen::Matrix3d to_world = s.camera.R().transpose();
  for (int i = 0; i < 12; ++i) {
    // Centres on tile corners and edges (tiles of kTileSize pixels).
    const double u = kTileSize * (1 + i % 3) + (i % 2 ? 0.3 : -2.6);
    const double v = kTileSize * (1 + (i / 3) % 2) + 3.7 * uni(rng) - 1.8;
    const double z = 3 + uni(rng);
    const bool round = i % 4 == 3;
    // Needles: sigma 5-7 px long, 0.3-0.6 px across; round: 4-5 px.
    const double long_px = round ? 4 + uni(rng) : 5 + 2 * uni(rng);
    const double thin_px = round ? long_px : 0.3 + 0.3 * uni(rng);
    const Eigen::Vector3d scale(long_px * z / f, thin_px * z / f,
                                thin_px * z / f);
    // Rotated in the image plane: the camera's z axis in the world.
    const double angle = 0.15 + 0.53 * i;
    const Eigen::Quaterniond q(
        to_world * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())
                       .toRotationMatrix());
    s.Add(s.camera.Unproject(u, v, z), scale,
          Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), 0.5 + 2 * uni(rng));
  }
  for (int n = 0; n < s.count; ++n) {
    for (int c = 0; c < 3; ++c) s.sh[3 * n + c] = uni(rng) * 2 - 1;
    s.extra[n] = uni(rng);
  }
  return s;
}

}  // namespace reference
}  // namespace es

#endif  // EULERSPLAT_TESTS_RASTER_TEST_SCENE_H_
