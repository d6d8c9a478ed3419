// Google Benchmark of Stage 1 on the device (solvers/train/cuda/
// device_static_trainer.h): training iterations per second on a synthetic
// 1168x880 scene, the random Gaussians of the rasterizer benchmarks
// (apps/common/raster_bench_scene.h) seen from four cameras, with masks
// (the mask term on, as es_static trains by default).
//
//   build/bin/bench_cuda_static --benchmark_counters_tabular=true
//
// Args: width, height, Gaussians. The targets are rendered once on the
// CPU from the scene; training starts from it with perturbed colours and
// opacities, densification off (its host round trip comes every hundred
// steps; this times the steps between). Each iteration is one
// DeviceStaticTrainer::Step (the loss comes back to the host, so the
// device is done when it returns). Prints why and exits with status 0
// when no CUDA device is present.

#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "apps/common/raster_bench_scene.h"
#include "apps/cuda/cuda_benchmark_main.h"
#include "core/render/cuda/cuda_error.h"
#include "core/render/rasterizer.h"
#include "solvers/train/cuda/device_static_trainer.h"

namespace es {
namespace cuda {
namespace {

constexpr int kFrames = 4;

struct TrainingScene {
  std::vector<Frame> frames;
  std::vector<int> train;
  GaussianSet initial;
};

TrainingScene MakeTrainingScene(int width, int height, int count) {
  BenchScene scene = MakeScene(width, height, count);
  // The water mask: the extra channel thresholded per Gaussian.
  for (double& e : scene.extra) e = e > 0.5 ? 1.0 : 0.0;
  TrainingScene t;
  Rasterizer rasterizer;
  RenderResult render;
  for (int k = 0; k < kFrames; ++k) {
    Frame f;
    f.camera = scene.camera;
    f.camera.t_cw += Eigen::Vector3d(0.05 * k, -0.03 * k, 0);
    rasterizer.Forward(f.camera, scene.View(), RenderOptions(), &render);
    cv::Mat(height, width, CV_64FC3, render.rgb.data())
        .convertTo(f.image, CV_32F);
    cv::Mat(height, width, CV_64FC1, render.extra.data())
        .convertTo(f.mask, CV_32F);
    t.frames.push_back(f);
    t.train.push_back(k);
  }
  t.initial = scene.gaussians;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (double& v : t.initial.sh) v += noise(rng);
  for (double& v : t.initial.opacity_logits) v += noise(rng);
  return t;
}

// Google Benchmark calls a benchmark more than once to size its runs:
// each scene is made (rendered on the CPU) once.
const TrainingScene& SceneOf(int width, int height, int count) {
  static std::map<std::tuple<int, int, int>, TrainingScene> scenes;
  const auto key = std::make_tuple(width, height, count);
  auto it = scenes.find(key);
  if (it == scenes.end())
    it = scenes.emplace(key, MakeTrainingScene(width, height, count)).first;
  return it->second;
}

void BM_CudaStaticStep(benchmark::State& state) {
  const TrainingScene& scene =
      SceneOf(state.range(0), state.range(1), state.range(2));
  StaticTrainerOptions options;
  options.iterations = 1000000;  // the learning-rate schedule's length
  options.max_sh_degree = 3;
  options.sh_degree_interval = 1000000;  // stays at the scene's degree
  options.densify = false;
  DeviceStaticTrainer trainer(&scene.frames, scene.train, options,
                              scene.initial);
  trainer.Step();  // untimed: buffers are allocated once, as in training
  double loss = 0;
  for (auto _ : state) loss = trainer.Step().loss;
  benchmark::DoNotOptimize(loss);
  state.counters["it/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["loss"] = loss;
}

BENCHMARK(BM_CudaStaticStep)
    ->ArgNames({"w", "h", "n"})
    ->Args({1168, 880, 100000})
    ->Args({1168, 880, 300000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace cuda
}  // namespace es

int main(int argc, char** argv) {
  return es::cuda::RunCudaBenchmarks("bench_cuda_static", argc, argv);
}
