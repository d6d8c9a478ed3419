#ifndef EULERSPLAT_APPS_CUDA_TRAINING_BENCH_SCENE_H_
#define EULERSPLAT_APPS_CUDA_TRAINING_BENCH_SCENE_H_

// The device trainers' benchmark scene: the random Gaussians of the
// rasterizer benchmarks (apps/common/raster_bench_scene.h) seen from four
// cameras, one video frame each, with water masks (the Gaussians whose
// extra channel is set, which also start as water). The targets are
// rendered once on the CPU; training starts from the scene with perturbed
// colours and opacities.

#include <map>
#include <random>
#include <tuple>
#include <vector>

#include <opencv2/core.hpp>

#include "apps/common/raster_bench_scene.h"
#include "core/io/scene.h"
#include "core/render/rasterizer.h"

namespace es {
namespace cuda {

constexpr int kBenchFrames = 4;

struct TrainingScene {
  std::vector<Frame> frames;
  std::vector<int> train;
  GaussianSet initial;
};

inline TrainingScene MakeTrainingScene(int width, int height, int count) {
  BenchScene scene = MakeScene(width, height, count);
  // The water mask: the extra channel thresholded per Gaussian.
  for (double& e : scene.extra) e = e > 0.5 ? 1.0 : 0.0;
  TrainingScene t;
  Rasterizer rasterizer;
  RenderResult render;
  for (int k = 0; k < kBenchFrames; ++k) {
    Frame f;
    f.camera = scene.camera;
    f.camera.t_cw += Eigen::Vector3d(0.05 * k, -0.03 * k, 0);
    f.time_index = k;
    rasterizer.Forward(f.camera, scene.View(), RenderOptions(), &render);
    cv::Mat(height, width, CV_64FC3, render.rgb.data())
        .convertTo(f.image, CV_32F);
    cv::Mat(height, width, CV_64FC1, render.extra.data())
        .convertTo(f.mask, CV_32F);
    t.frames.push_back(f);
    t.train.push_back(k);
  }
  t.initial = scene.gaussians;
  // The masked Gaussians start as water (for Stage 3's dynamic set).
  for (int i = 0; i < t.initial.size(); ++i)
    t.initial.dynamic_logits[i] = scene.extra[i] > 0.5 ? 3.0 : -3.0;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (double& v : t.initial.sh) v += noise(rng);
  for (double& v : t.initial.opacity_logits) v += noise(rng);
  return t;
}

// Google Benchmark calls a benchmark more than once to size its runs:
// each scene is made (rendered on the CPU) once.
inline const TrainingScene& SceneOf(int width, int height, int count) {
  static std::map<std::tuple<int, int, int>, TrainingScene> scenes;
  const auto key = std::make_tuple(width, height, count);
  auto it = scenes.find(key);
  if (it == scenes.end())
    it = scenes.emplace(key, MakeTrainingScene(width, height, count)).first;
  return it->second;
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_APPS_CUDA_TRAINING_BENCH_SCENE_H_
