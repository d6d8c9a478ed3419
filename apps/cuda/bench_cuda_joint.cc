// Google Benchmark of Stage 3 on the device (solvers/train/cuda/
// device_joint_trainer.h): joint training iterations per second on the
// synthetic 1168x880 scene of the device trainers' benchmarks
// (apps/cuda/training_bench_scene.h), whose masked Gaussians (about half)
// are water: the Euler chain of V over them, D, the mask term, and with
// energy = 1 the water-energy pairs that es_train runs by default (two
// renders per iteration).
//
//   build/bin/bench_cuda_joint --benchmark_counters_tabular=true
//
// Args: width, height, Gaussians, energy. V and D have es_train's default
// shapes, the cycle length is 4 (the scene's four frames; the default
// training cycle of 15 frames means up to 14 Euler steps, here up to 3,
// so the chain's share grows with L). Water densification and the
// dynamic set's refresh are off: their host round trips come every tens
// of steps, this times the steps between. Each iteration is one
// DeviceJointTrainer::Step (the loss comes back to the host, so the
// device is done when it returns). Prints why and exits with status 0
// when no CUDA device is present.

#include <optional>

#include <benchmark/benchmark.h>

#include "apps/cuda/cuda_benchmark_main.h"
#include "apps/cuda/training_bench_scene.h"
#include "solvers/train/cuda/device_joint_trainer.h"

namespace es {
namespace cuda {
namespace {

void BM_CudaJointStep(benchmark::State& state) {
  const TrainingScene& scene =
      SceneOf(state.range(0), state.range(1), state.range(2));
  JointTrainerOptions options;
  options.iterations = 1000000;  // the learning-rate schedule's length
  options.cycle_length = kBenchFrames;
  options.refresh_interval = 1000000;
  if (state.range(3) != 0) options.water_energy = WaterEnergyOptions();
  DeviceJointTrainer trainer(&scene.frames, scene.train, options,
                             scene.initial, std::nullopt);
  trainer.Step();  // untimed: buffers are allocated once, as in training
  JointIterationStats stats;
  // No DoNotOptimize(stats.loss) after the loop: Google Benchmark 1.7's,
  // compiled by GCC 12, leaves garbage in the value it is given.
  for (auto _ : state) stats = trainer.Step();
  state.counters["it/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["loss"] = stats.loss;
  state.counters["water"] = stats.num_dynamic;
}

BENCHMARK(BM_CudaJointStep)
    ->ArgNames({"w", "h", "n", "energy"})
    ->Args({1168, 880, 100000, 0})
    ->Args({1168, 880, 100000, 1})
    ->Args({1168, 880, 300000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace cuda
}  // namespace es

ES_CUDA_BENCHMARK_MAIN("bench_cuda_joint")
