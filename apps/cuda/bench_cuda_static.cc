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


#include <benchmark/benchmark.h>

#include "apps/cuda/cuda_benchmark_main.h"
#include "apps/cuda/training_bench_scene.h"
#include "solvers/train/cuda/device_static_trainer.h"

namespace es {
namespace cuda {
namespace {

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
  // No DoNotOptimize(loss) after the loop: Google Benchmark 1.7's,
  // compiled by GCC 12, leaves garbage in the value it is given.
  for (auto _ : state) loss = trainer.Step().loss;
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

ES_CUDA_BENCHMARK_MAIN("bench_cuda_static")
