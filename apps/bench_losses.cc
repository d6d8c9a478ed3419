// Google Benchmark of the image losses with their image gradients, as
// training calls them once per iteration:
// - the photometric loss (L1 + SSIM): a rendering scored against one of a
//   few targets in turn, in float (training) or double (tests), with the
//   targets' SSIM statistics cached or recomputed. Args: width, height,
//   threads, double, cache (1: statistics kept), simd (0 auto, 1 SSE2,
//   2 AVX2, 3 AVX-512; levels the CPU lacks are skipped);
// - the water energy loss (motion and detail terms) of a rendered frame
//   pair against the input pair, with masks. Args: width, height, threads;
// - the water texture loss (sliced Wasserstein, es_train --texture_weight)
//   of one rendered frame against its input, with its gradient, over a
//   water mask covering the `water` percent of the frame. Args: width,
//   height, water percent, projections.
//
//   build/bin/bench_losses --benchmark_counters_tabular=true

#include <omp.h>

#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "apps/common/benchmark_main.h"
#include "costs/photometric_loss.h"
#include "costs/water_energy_loss.h"
#include "costs/water_texture_loss.h"

namespace es {
namespace {

constexpr int kTargets = 4;

cv::Mat RandomImage(int width, int height, uint32_t seed) {
  cv::Mat m(height, width, CV_32FC3);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
  return m;
}

void BM_PhotometricLoss(benchmark::State& state) {
  const int width = state.range(0), height = state.range(1);
  omp_set_num_threads(state.range(2));
  const bool use_double = state.range(3) != 0;
  const bool cache = state.range(4) != 0;
  const auto level = static_cast<SimdLevel>(state.range(5));
  if (!SimdLevelSupported(level)) {
    state.SkipWithError("the CPU lacks this instruction set");
    return;
  }
  std::vector<cv::Mat> targets;
  for (int i = 0; i < kTargets; ++i) {
    cv::Mat y = RandomImage(width, height, 10 + i);
    if (use_double) y.convertTo(y, CV_64FC3);
    targets.push_back(y);
  }
  cv::Mat rendered;
  RandomImage(width, height, 1).convertTo(rendered, CV_64FC3);
  std::vector<double> grad(rendered.total() * 3);
  PhotometricLoss loss(0.2, use_double, cache ? size_t{1} << 30 : 0, level);
  for (const cv::Mat& y : targets)  // warm buffers (and the cache)
    loss.Evaluate(rendered.ptr<double>(), y, 1.0, grad.data());
  int next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(loss.Evaluate(
        rendered.ptr<double>(), targets[next], 1.0, grad.data()));
    next = (next + 1) % kTargets;
  }
  state.counters["values/s"] = benchmark::Counter(
      static_cast<double>(rendered.total() * 3) * state.iterations(),
      benchmark::Counter::kIsRate);
  omp_set_num_threads(omp_get_num_procs());
}

void Sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"w", "h", "threads", "double", "cache", "simd"});
  const auto kSse2 = static_cast<int>(SimdLevel::kSse2);
  const auto kAvx512 = static_cast<int>(SimdLevel::kAvx512);
  for (int threads : {1, 2}) {
    for (const auto& size : {std::pair{320, 240}, std::pair{1168, 880}}) {
      for (int simd = kSse2; simd <= kAvx512; ++simd)
        b->Args({size.first, size.second, threads, 0, 1, simd});
      b->Args({size.first, size.second, threads, 0, 0, 0});
      b->Args({size.first, size.second, threads, 1, 1, 0});
    }
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

BENCHMARK(BM_PhotometricLoss)->Apply(Sizes);

void BM_WaterEnergyLoss(benchmark::State& state) {
  const int width = state.range(0), height = state.range(1);
  omp_set_num_threads(state.range(2));
  const cv::Mat input_a = RandomImage(width, height, 20);
  const cv::Mat input_b = RandomImage(width, height, 21);
  cv::Mat mask_a(height, width, CV_32FC1), mask_b(height, width, CV_32FC1);
  cv::RNG(22).fill(mask_a, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::RNG(23).fill(mask_b, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::Mat rendered_a, rendered_b;
  RandomImage(width, height, 2).convertTo(rendered_a, CV_64FC3);
  RandomImage(width, height, 3).convertTo(rendered_b, CV_64FC3);
  std::vector<double> grad_a(rendered_a.total() * 3),
      grad_b(rendered_b.total() * 3);
  WaterEnergyLoss loss;
  for (auto _ : state) {
    benchmark::DoNotOptimize(loss.Evaluate(
        rendered_a.ptr<double>(), rendered_b.ptr<double>(), input_a, input_b,
        mask_a, mask_b, 1.0, grad_a.data(), grad_b.data()));
  }
  omp_set_num_threads(omp_get_num_procs());
}

BENCHMARK(BM_WaterEnergyLoss)
    ->ArgNames({"w", "h", "threads"})
    ->Args({160, 120, 1})
    ->Args({160, 120, 2})
    ->Args({320, 240, 1})
    ->Args({320, 240, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_WaterTextureLoss(benchmark::State& state) {
  const int width = state.range(0), height = state.range(1);
  const cv::Mat input = RandomImage(width, height, 30);
  // The water: the left `water` percent of the columns.
  cv::Mat mask(height, width, CV_32FC1, cv::Scalar(0.0));
  mask.colRange(0, static_cast<int>(width * state.range(2) / 100))
      .setTo(cv::Scalar(1.0));
  cv::Mat rendered;
  RandomImage(width, height, 31).convertTo(rendered, CV_64FC3);
  std::vector<double> grad(rendered.total() * 3);
  WaterTextureOptions options;
  options.weight = 1.0;
  options.projections = static_cast<int>(state.range(3));
  WaterTextureLoss loss(options);
  uint64_t draw = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(loss.Evaluate(rendered.ptr<double>(), input,
                                           mask, 1.0, draw++, grad.data()));
  }
}

BENCHMARK(BM_WaterTextureLoss)
    ->ArgNames({"w", "h", "water", "projections"})
    ->Args({160, 120, 40, 16})
    ->Args({160, 120, 100, 16})
    ->Args({320, 240, 40, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

}  // namespace
}  // namespace es

int main(int argc, char** argv) { return es::RunBenchmarks(argc, argv); }
