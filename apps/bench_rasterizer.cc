// Google Benchmark of the splat rasterizer: forward and forward + backward on
// random scenes, in float and double, on 1 and 2 threads, with the tile
// kernels of each instruction set (float) or the CPU's best (double).
//
//   build/bin/bench_rasterizer --benchmark_counters_tabular=true
//
// Args: width, height, Gaussians, threads, use_double, simd (0 auto, 1
// SSE2, 2 AVX2, 3 AVX-512; levels the CPU lacks are skipped). Counters:
// visible Gaussians and Gaussian-pixel pairs evaluated per second (pairs/s);
// on one thread also each stage's wall ms per pass (project_ms: projection
// and packing the tile data, bin_sort_ms, fwd_tiles_ms, bwd_tiles_ms,
// project_bwd_ms: summing each Gaussian's tile shares and the chain to 3D).
//
// BM_TileSplit simulates the tile passes on more threads than the machine
// has: each tile's cost is the Gaussian-pixel pairs the forward pass
// evaluates in it (recomputed from the projection, early stop included),
// handed out as the rasterizer's schedule(dynamic, 1) hands out tiles
// (core/base/schedule_simulation.h). Counters: speedup (one thread's
// work over the simulated makespan, an upper bound: no scheduling overhead
// or memory contention), largest_tile (the costliest tile's share of the
// work; 1 / largest_tile bounds any speedup) and pairs_model (the modelled
// pairs over those the forward pass counted, 1 when the model is exact).

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "apps/common/benchmark_main.h"
#include "apps/common/raster_bench_scene.h"
#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/base/schedule_simulation.h"
#include "core/base/stage_profile.h"
#include "core/render/raster_constants.h"
#include "core/render/raster_project.h"
#include "core/render/rasterizer.h"

namespace es {
namespace {

void Run(benchmark::State& state, bool backward) {
  const int width = state.range(0), height = state.range(1);
  const BenchScene scene = MakeScene(width, height, state.range(2));
  omp_set_num_threads(state.range(3));
  RenderOptions options;
  options.use_double = state.range(4) != 0;
  options.simd = static_cast<SimdLevel>(state.range(5));
  if (!SimdLevelSupported(options.simd)) {
    state.SkipWithError("the CPU lacks this instruction set");
    return;
  }
  const SplatView view = scene.View();
  const BenchImageGrads grads(width * height);
  Rasterizer rasterizer;
  RenderResult result;
  SplatGradients splat_grads;
  // One untimed pass first: its buffers are allocated and first touched
  // once (the gradient shares of every tile entry: ~100 MB at 1168x880 /
  // 300k), as a training run's rasterizer has them from earlier frames.
  rasterizer.Forward(scene.camera, view, options, &result);
  if (backward) {
    rasterizer.Backward({grads.rgb.data(), grads.alpha.data(),
                         grads.depth.data(), grads.extra.data()},
                        &splat_grads);
  }
  // Per-stage wall time (only on one thread: stages inside a parallel
  // region are not timed by StageProfile).
  StageProfile& profile = StageProfile::Get();
  profile.Start(state.range(3) == 1);
  for (auto _ : state) {
    rasterizer.Forward(scene.camera, view, options, &result);
    if (backward) {
      rasterizer.Backward({grads.rgb.data(), grads.alpha.data(),
                           grads.depth.data(), grads.extra.data()},
                          &splat_grads);
    }
    benchmark::DoNotOptimize(result.rgb.data());
  }
  if (StageProfile::On()) {
    const std::pair<const char*, Stage> kStages[] = {
        {"project_ms", Stage::kProjection},
        {"bin_sort_ms", Stage::kBinSort},
        {"fwd_tiles_ms", Stage::kForwardTiles},
        {"bwd_tiles_ms", Stage::kBackwardTiles},
        {"project_bwd_ms", Stage::kProjectionBackward}};
    for (const auto& [name, stage] : kStages) {
      state.counters[name] =
          1e-6 * profile.nanoseconds(stage) / state.iterations();
    }
    profile.Enable(false);
  }
  state.counters["visible"] = rasterizer.num_visible();
  state.counters["pairs/s"] = benchmark::Counter(
      static_cast<double>(rasterizer.num_pair_evaluations()) *
          state.iterations(),
      benchmark::Counter::kIsRate);
  omp_set_num_threads(omp_get_num_procs());
}

void BM_Forward(benchmark::State& state) { Run(state, false); }
void BM_ForwardBackward(benchmark::State& state) { Run(state, true); }

void Sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"w", "h", "n", "threads", "double", "simd"});
  const auto kSse2 = static_cast<int>(SimdLevel::kSse2);
  const auto kAvx512 = static_cast<int>(SimdLevel::kAvx512);
  for (int use_double : {0, 1}) {
    for (int threads : {1, 2}) {
      for (int simd = use_double ? 0 : kSse2;
           simd <= (use_double ? 0 : kAvx512); ++simd) {
        b->Args({320, 240, 10000, threads, use_double, simd});
        b->Args({320, 240, 100000, threads, use_double, simd});
        b->Args({1168, 880, 300000, threads, use_double, simd});
      }
    }
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

// Per tile (row-major), the Gaussian-pixel pairs the forward pass
// evaluates there: each binned Gaussian's pixel box within the tile, in
// depth order, until every pixel of the tile has stopped (its transmittance
// would fall below kMinTransmittance), as the tile pass composites (here
// in double, so a pixel on the edge of a threshold may stop one Gaussian
// apart: pairs_model checks the total).
std::vector<double> TilePairs(const Camera& camera, const SplatView& view) {
  const ProjectionCamera cam(camera);
  std::vector<ProjectedSplat> splats;
  std::vector<int> index;
  for (int i = 0; i < view.count; ++i) {
    ProjectedSplat p;
    if (!ProjectSplat(cam, view, i, &p)) continue;
    splats.push_back(p);
    index.push_back(static_cast<int>(index.size()));
  }
  std::sort(index.begin(), index.end(), [&splats](int a, int b) {
    const double da = splats[a].depth, db = splats[b].depth;
    return da < db || (da == db && a < b);
  });
  const int tiles = cam.tiles_x * cam.tiles_y;
  std::vector<std::vector<int>> lists(tiles);
  for (int k : index) {
    const ProjectedSplat& p = splats[k];
    for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
      for (int tx = p.tile_x0; tx < p.tile_x1; ++tx)
        lists[ty * cam.tiles_x + tx].push_back(k);
    }
  }
  std::vector<double> pairs(tiles, 0.0);
  for (int tile = 0; tile < tiles; ++tile) {
    const int x0 = (tile % cam.tiles_x) * kTileSize;
    const int y0 = (tile / cam.tiles_x) * kTileSize;
    const int x1 = std::min(x0 + kTileSize, cam.width);
    const int y1 = std::min(y0 + kTileSize, cam.height);
    double t[kTileSize * kTileSize];
    bool done[kTileSize * kTileSize] = {};
    std::fill(t, t + kTileSize * kTileSize, 1.0);
    int active = (x1 - x0) * (y1 - y0);
    for (size_t e = 0; e < lists[tile].size() && active > 0; ++e) {
      const ProjectedSplat& p = splats[lists[tile][e]];
      const int bx0 = std::max(x0, p.px0), bx1 = std::min(x1, p.px1);
      const int by0 = std::max(y0, p.py0), by1 = std::min(y1, p.py1);
      if (bx1 <= bx0 || by1 <= by0) continue;
      pairs[tile] += double(bx1 - bx0) * (by1 - by0);
      for (int y = by0; y < by1; ++y) {
        for (int x = bx0; x < bx1; ++x) {
          const int q = (y - y0) * kTileSize + (x - x0);
          if (done[q]) continue;
          const double dx = x + 0.5 - p.mean2d[0], dy = y + 0.5 - p.mean2d[1];
          const double sigma =
              0.5 * (p.conic[0] * dx * dx + p.conic[2] * dy * dy) +
              p.conic[1] * dx * dy;
          const double alpha =
              std::min(kMaxAlpha, p.opacity * std::exp(-sigma));
          if (sigma < 0 || alpha < kMinAlpha) continue;
          const double next = t[q] * (1 - alpha);
          if (next < kMinTransmittance) {
            done[q] = true;
            --active;
          } else {
            t[q] = next;
          }
        }
      }
    }
  }
  return pairs;
}

void BM_TileSplit(benchmark::State& state) {
  const int width = state.range(0), height = state.range(1);
  const BenchScene scene = MakeScene(width, height, state.range(2));
  const int threads = state.range(3);
  const SplatView view = scene.View();
  Rasterizer rasterizer;
  RenderResult result;
  rasterizer.Forward(scene.camera, view, RenderOptions(), &result);
  const std::vector<double> pairs = TilePairs(scene.camera, view);
  double total = 0, largest = 0;
  for (double p : pairs) {
    total += p;
    largest = std::max(largest, p);
  }
  double makespan = 0;
  for (auto _ : state) {
    makespan = DynamicScheduleMakespan(pairs, threads, 1);
    benchmark::DoNotOptimize(makespan);
  }
  state.counters["tiles"] = static_cast<double>(pairs.size());
  state.counters["speedup"] = total / makespan;
  state.counters["largest_tile"] = largest / total;
  state.counters["pairs_model"] =
      total / static_cast<double>(rasterizer.num_pair_evaluations());
}

BENCHMARK(BM_Forward)->Apply(Sizes);
BENCHMARK(BM_ForwardBackward)->Apply(Sizes);
BENCHMARK(BM_TileSplit)->Apply([](benchmark::internal::Benchmark* b) {
  b->ArgNames({"w", "h", "n", "threads"});
  for (int threads : {1, 2, 4, 8, 16}) {
    b->Args({320, 240, 10000, threads});
    b->Args({1168, 880, 300000, threads});
  }
});

}  // namespace
}  // namespace es

int main(int argc, char** argv) { return es::RunBenchmarks(argc, argv); }
