#ifndef EULERSPLAT_TESTS_TINY_LOOP_SCENE_H_
#define EULERSPLAT_TESTS_TINY_LOOP_SCENE_H_

// A tiny looping scene for the Stage 3 trainers' tests (CPU and device):
// frames rendered from a known canonical model whose water Gaussians
// translate and jump back every kCycle frames, with water masks.

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "core/flow/flow_lifting.h"
#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "solvers/train/joint_stage_trainer.h"
#include "tests/centered_camera.h"
#include "tests/small_fields.h"

namespace es {
namespace tiny_loop {

constexpr int kCycle = 4;
constexpr int kFrames = 12;
constexpr int kWidth = 32, kHeight = 24;
constexpr int kNumStatic = 6, kNumDynamic = 4;
// The true motion: every dynamic Gaussian moves this much per frame and
// jumps back to its canonical position every kCycle frames.
inline const Eigen::Vector3d kVelocity(0.06, 0.02, 0.0);

inline Camera TinyCamera(int i) {
  Camera c = CenteredCamera(kWidth, kHeight, 30);
  c.t_cw = {0.02 * std::sin(i), 0.01 * std::cos(i), 0.0};
  return c;
}

// Static Gaussians on a back plane, dynamic ones in front of it.
inline GaussianSet TrueCanonical() {
  GaussianSet g;
  g.sh_degree = 0;
  g.Resize(kNumStatic + kNumDynamic);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < g.size(); ++i) {
    const bool dynamic = i >= kNumStatic;
    g.means[3 * i] = (dynamic ? 0.25 : 0.5) * u(rng) - (dynamic ? 0.1 : 0.0);
    g.means[3 * i + 1] = (dynamic ? 0.2 : 0.4) * u(rng);
    g.means[3 * i + 2] = dynamic ? 2.0 + 0.1 * (i - kNumStatic) : 3.0;
    for (int a = 0; a < 3; ++a)
      g.log_scales[3 * i + a] = std::log(dynamic ? 0.06 : 0.2);
    g.opacity_logits[i] = dynamic ? 1.0 : 2.0;
    for (int c = 0; c < 3; ++c) g.sh[3 * i + c] = 1.2 * u(rng);
    g.dynamic_logits[i] = dynamic ? 3.0 : -3.0;
  }
  return g;
}

// Frames rendered from the true looping motion (all loops start at 0).
inline std::vector<Frame> TrueFrames() {
  const GaussianSet canonical = TrueCanonical();
  Rasterizer rasterizer;
  RenderResult render;
  std::vector<Frame> frames(kFrames);
  for (int i = 0; i < kFrames; ++i) {
    GaussianSet g = canonical;
    for (int n = kNumStatic; n < g.size(); ++n)
      for (int j = 0; j < 3; ++j)
        g.means[3 * n + j] += kVelocity[j] * (i % kCycle);
    frames[i].camera = TinyCamera(i);
    frames[i].time_index = i;
    rasterizer.Forward(frames[i].camera, SplatView::Of(g), RenderOptions(),
                       &render);
    cv::Mat(kHeight, kWidth, CV_64FC3, render.rgb.data())
        .convertTo(frames[i].image, CV_32FC3);
    // Water where a dynamic Gaussian is within 2 sigma of the pixel.
    frames[i].mask = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(0.f));
    for (int n = kNumStatic; n < g.size(); ++n) {
      const Eigen::Vector2d uv = frames[i].camera.Project(
          frames[i].camera.WorldToCamera(Eigen::Vector3d(&g.means[3 * n])));
      cv::circle(frames[i].mask, cv::Point(uv.x(), uv.y()), 2,
                 cv::Scalar(1.f), -1);
    }
  }
  return frames;
}

// Scene-flow samples of velocity `v` around the dynamic Gaussians.
inline std::vector<SceneFlowSample> FlowSamples(const Eigen::Vector3d& v) {
  const GaussianSet g = TrueCanonical();
  std::mt19937 rng(4);
  std::normal_distribution<double> jitter(0, 0.05);
  std::vector<SceneFlowSample> samples;
  for (int n = kNumStatic; n < g.size(); ++n) {
    for (int k = 0; k < 50; ++k) {
      const Eigen::Vector3d x = Eigen::Vector3d(&g.means[3 * n]) +
                                Eigen::Vector3d(jitter(rng), jitter(rng),
                                                jitter(rng));
      samples.push_back({x, v});
    }
  }
  return samples;
}

// Stage 3 options for the scene: its cycle, fields small enough for tests,
// all loops starting at 0, no mask term.
inline JointTrainerOptions TinyOptions() {
  JointTrainerOptions o;
  o.iterations = 200;
  o.cycle_length = kCycle;
  o.random_start = false;
  o.mask_weight = 0;
  SetFieldSize(8, 4, 16, &o.motion);
  o.motion.velocity_scale = 0.05;
  SetFieldSize(8, 4, 16, &o.residual);
  o.lr_motion_triplane = 1e-2;
  o.lr_motion_mlp = 1e-2;
  return o;
}

}  // namespace tiny_loop
}  // namespace es

#endif  // EULERSPLAT_TESTS_TINY_LOOP_SCENE_H_
