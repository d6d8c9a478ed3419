// Google Benchmark of the CUDA rasterizer (core/render/cuda): forward and
// forward + backward on the device, on the random scenes of the CPU
// benchmark (apps/bench_rasterizer.cc, apps/common/raster_bench_scene.h).
//
//   build/bin/bench_cuda_rasterizer --benchmark_counters_tabular=true
//
// Args: width, height, Gaussians. The splats, images and gradients stay
// on the device (ForwardDevice / BackwardDevice, as training will run
// them); each iteration ends when the device is done (a download of the
// visible count and entries is the only traffic besides). Counters:
// visible Gaussians, (Gaussian, tile) entries binned. Prints why and exits
// with status 0 when no CUDA device is present.

#include <cstdio>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "apps/common/raster_bench_scene.h"
#include "apps/cuda/cuda_benchmark_main.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "core/render/cuda/device_splats.h"

namespace es {
namespace cuda {
namespace {

std::vector<float> AsFloat(const std::vector<double>& v) {
  return std::vector<float>(v.begin(), v.end());
}

void Run(benchmark::State& state, bool backward) {
  const int width = state.range(0), height = state.range(1);
  const BenchScene scene = MakeScene(width, height, state.range(2));
  DeviceSplats splats;
  splats.Upload(scene.View());
  const DeviceSplatView view = splats.View();

  const BenchImageGrads grads(width * height);
  DeviceBuffer<float> d_rgb, d_alpha, d_depth, d_extra;
  d_rgb.Upload(AsFloat(grads.rgb));
  d_alpha.Upload(AsFloat(grads.alpha));
  d_depth.Upload(AsFloat(grads.depth));
  d_extra.Upload(AsFloat(grads.extra));
  DeviceGradientArrays splat_grads;
  splat_grads.Resize(view.count, view.sh_degree, view.num_extra);
  const DeviceImageGradients image_grads = {d_rgb.data(), d_alpha.data(),
                                            d_depth.data(), d_extra.data()};

  DeviceRasterizer rasterizer;
  const Eigen::Vector3d background(0, 0, 0);
  // One untimed pass: buffers are allocated once, as in training.
  rasterizer.ForwardDevice(scene.camera, view, background);
  if (backward) rasterizer.BackwardDevice(image_grads, splat_grads.View());
  float sink = 0;
  for (auto _ : state) {
    const DeviceImages& images =
        rasterizer.ForwardDevice(scene.camera, view, background);
    if (backward) rasterizer.BackwardDevice(image_grads, splat_grads.View());
    // Waits for the device: the iteration's work is done.
    CopyToHost(&sink, images.rgb, sizeof(sink));
  }
  benchmark::DoNotOptimize(sink);
  state.counters["visible"] = rasterizer.num_visible();
  state.counters["entries"] = rasterizer.num_entries();
}

void BM_CudaForward(benchmark::State& state) { Run(state, false); }
void BM_CudaForwardBackward(benchmark::State& state) { Run(state, true); }

void Sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"w", "h", "n"});
  b->Args({320, 240, 10000});
  b->Args({1168, 880, 300000});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_CudaForward)->Apply(Sizes);
BENCHMARK(BM_CudaForwardBackward)->Apply(Sizes);

}  // namespace
}  // namespace cuda
}  // namespace es

ES_CUDA_BENCHMARK_MAIN("bench_cuda_rasterizer")
