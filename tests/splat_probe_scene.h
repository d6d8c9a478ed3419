#ifndef EULERSPLAT_TESTS_SPLAT_PROBE_SCENE_H_
#define EULERSPLAT_TESTS_SPLAT_PROBE_SCENE_H_

// The tiny frame and Gaussians the cost-functor gradient tests probe: small
// enough for Ceres' numeric Jacobians, with every parameter block affecting
// the loss.

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "tests/centered_camera.h"

namespace es {
namespace probe_scene {

constexpr int kWidth = 24, kHeight = 20;

// A 24x20 frame seen by a slightly rotated camera, a textured image and a
// mask whose lower half is water.
inline Frame TinyFrame() {
  Frame f;
  f.camera = CenteredCamera(kWidth, kHeight, 20);
  f.camera.q_cw = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.3, 1, 0).normalized()));
  f.camera.t_cw = {0.1, -0.05, 0.2};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  f.image.create(kHeight, kWidth, CV_32FC3);
  for (int i = 0; i < kHeight; ++i)
    for (int j = 0; j < kWidth; ++j)
      f.image.at<cv::Vec3f>(i, j) = {0.2f + 0.5f * u(rng), 0.4f, 0.05f * j};
  f.mask = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(0.f));
  f.mask.rowRange(10, kHeight).setTo(1.f);
  return f;
}

// Six Gaussians of SH degree 1 in front of the camera, opacities and sizes
// away from the rasterizer's clamps so the loss is smooth at the probe
// (opacity < 0.35 keeps alpha below 1/255 outside the 3-sigma tiles).
inline GaussianSet SixGaussians() {
  GaussianSet g;
  g.sh_degree = 1;
  g.Resize(6);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 6; ++i) {
    g.means[3 * i] = 0.5 * u(rng);
    g.means[3 * i + 1] = 0.4 * u(rng);
    // Well-separated depths: a depth-order swap is a true discontinuity.
    g.means[3 * i + 2] = 2.5 + 0.2 * i;
    for (int a = 0; a < 3; ++a)
      g.log_scales[3 * i + a] = std::log(0.25) + 0.3 * u(rng);
    for (int a = 0; a < 4; ++a) g.quats[4 * i + a] = (a == 0) + 0.3 * u(rng);
    g.opacity_logits[i] = -1.2 + 0.3 * u(rng);
    for (int k = 0; k < 12; ++k)
      g.sh[12 * i + k] = (k < 3 ? 0.8 : 0.3) * u(rng);
    g.dynamic_logits[i] = u(rng);
  }
  return g;
}

// Double-precision rendering on a coloured background (so the background
// term is exercised too).
inline RenderOptions DoubleOptions() {
  RenderOptions o;
  o.use_double = true;
  o.background = {0.1, 0.2, 0.3};
  return o;
}

}  // namespace probe_scene
}  // namespace es

#endif  // EULERSPLAT_TESTS_SPLAT_PROBE_SCENE_H_
