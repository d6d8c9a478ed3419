// Looping animation cost: Alg. 1 (advect every Gaussian from its canonical
// position to its cycle index, every frame) against Alg. 2 (one Euler step
// per Gaussian per frame), and what one batched V evaluation costs.
//
//   bench_looping --benchmark_filter=Alg
//
// Arguments: {dynamic Gaussians, frames}, or {points, precision} of the
// fields' MLPs (0 double, 1 float: es_train's --motion_precision and
// --residual_precision). Defaults are the paper's field sizes
// (MotionFieldOptions, ResidualFieldOptions) and L = 15.

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "apps/common/benchmark_main.h"
#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/loop/cycle_time.h"
#include "core/loop/euler_chain.h"
#include "core/loop/loop_animator.h"

namespace es {
namespace {

constexpr int kCycleLength = 15;

struct Scene {
  explicit Scene(int n) : field(MotionFieldOptions()), x0(3 * n) {
    field.SetBox(Eigen::Vector3d(-1.0, -1.0, -1.0),
                 Eigen::Vector3d(1.0, 1.0, 1.0));
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& c : x0) c = uniform(rng);
    start_times = RandomStartTimes(n, kCycleLength, 2);
  }
  MotionField field;
  std::vector<double> x0;
  std::vector<int> start_times;
};

// The MLP precision of a benchmark's second argument.
MlpPrecision PrecisionArg(const benchmark::State& state) {
  return state.range(1) == 1 ? MlpPrecision::kFloat : MlpPrecision::kDouble;
}

void SetFrameCounters(benchmark::State& state, int frames, int64_t evals) {
  state.counters["frames"] = frames;
  state.counters["s_per_frame"] =
      benchmark::Counter(frames, benchmark::Counter::kIsIterationInvariantRate |
                                     benchmark::Counter::kInvert);
  state.counters["V_evals_per_frame"] = static_cast<double>(evals) / frames;
}

void BM_Alg1PerFrame(benchmark::State& state) {
  const int n = state.range(0), frames = state.range(1);
  Scene scene(n);
  EulerChain chain(&scene.field, EulerOptions());
  std::vector<int> steps(n);
  std::vector<double> x(3 * n);
  int64_t evals = 0;
  for (auto _ : state) {
    evals = 0;
    for (int i = 0; i < frames; ++i) {
      for (int k = 0; k < n; ++k) {
        steps[k] = CycleIndex(i, scene.start_times[k], kCycleLength);
      }
      chain.Forward(scene.field.params(), n, scene.x0.data(), steps.data(),
                    x.data());
      evals += chain.stats().velocity_evaluations;
      benchmark::DoNotOptimize(x.data());
    }
  }
  SetFrameCounters(state, frames, evals);
}

void BM_Alg2PerFrame(benchmark::State& state) {
  const int n = state.range(0), frames = state.range(1);
  Scene scene(n);
  LoopAnimator animator(&scene.field, EulerOptions(), kCycleLength);
  for (auto _ : state) {
    animator.Start(scene.field.params(), n, scene.x0.data(), scene.start_times,
                   0);
    for (int i = 1; i < frames; ++i) {
      animator.Advance(scene.field.params());
      benchmark::DoNotOptimize(animator.positions().data());
    }
  }
  SetFrameCounters(state, frames, animator.stats().velocity_evaluations);
}

// One batched V(x) over n points.
void BM_MotionFieldEvaluate(benchmark::State& state) {
  const int n = state.range(0);
  Scene scene(n);
  FieldWorkspace ws;
  std::vector<double> v(3 * n);
  for (auto _ : state) {
    scene.field.Evaluate(scene.field.params(), n, scene.x0.data(), v.data(),
                         &ws);
    benchmark::DoNotOptimize(v.data());
  }
  state.counters["s_per_point"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate |
                                benchmark::Counter::kInvert);
}

// Evaluate + Backward to all parameters and positions, as in training.
void BM_MotionFieldEvaluateBackward(benchmark::State& state) {
  const int n = state.range(0);
  Scene scene(n);
  MotionField& field = scene.field;
  field.set_mlp_precision(PrecisionArg(state));
  FieldWorkspace ws;
  std::vector<double> v(3 * n), d_v(3 * n, 1.0), d_x(3 * n);
  std::vector<double> d_triplane(field.triplane_params().size());
  std::vector<double> d_mlp(field.mlp_params().size());
  auto run = [&] {
    field.Evaluate(field.params(), n, scene.x0.data(), v.data(), &ws);
    field.Backward(field.params(), d_v.data(),
                   {d_triplane.data(), d_mlp.data()}, d_x.data(), &ws);
  };
  run();  // untimed: the workspace's first growth
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(d_x.data());
  }
}

// The residual field D over n Gaussians, forward and backward, as in
// training (once per Gaussian per iteration, not per Euler step).
void BM_ResidualFieldEvaluateBackward(benchmark::State& state) {
  const int n = state.range(0);
  Scene scene(n);
  ResidualField field{ResidualFieldOptions()};
  field.set_mlp_precision(PrecisionArg(state));
  std::vector<int> t(n), p(n, 0);
  for (int k = 0; k < n; ++k) {
    t[k] = CycleIndex(0, scene.start_times[k], kCycleLength);
  }
  FieldWorkspace ws;
  std::vector<double> out(kResidualDim * n), d_out(kResidualDim * n, 1.0);
  std::vector<double> d_triplane(field.triplane_params().size());
  std::vector<double> d_mlp(field.mlp_params().size());
  auto run = [&] {
    field.Evaluate(field.params(), n, scene.x0.data(), t.data(), p.data(),
                   out.data(), &ws);
    field.Backward(field.params(), d_out.data(),
                   {d_triplane.data(), d_mlp.data()}, nullptr, &ws);
  };
  run();  // untimed: the workspace's first growth
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(d_mlp.data());
  }
}

// One training frame of Alg. 1: forward and backward through the chain.
void BM_Alg1ForwardBackward(benchmark::State& state) {
  const int n = state.range(0);
  Scene scene(n);
  MotionField& field = scene.field;
  field.set_mlp_precision(PrecisionArg(state));
  EulerChain chain(&field, EulerOptions());
  std::vector<int> steps(n);
  for (int k = 0; k < n; ++k) {
    steps[k] = CycleIndex(0, scene.start_times[k], kCycleLength);
  }
  std::vector<double> x(3 * n), d_out(3 * n, 1.0), d_x0(3 * n);
  std::vector<double> d_triplane(field.triplane_params().size());
  std::vector<double> d_mlp(field.mlp_params().size());
  auto run = [&] {
    chain.Forward(field.params(), n, scene.x0.data(), steps.data(), x.data());
    chain.Backward(field.params(), d_out.data(),
                   {d_triplane.data(), d_mlp.data()}, d_x0.data());
  };
  run();  // untimed: the chain's first growth
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(d_x0.data());
  }
}

// Alg. 1's work per frame repeats with period L, so {n, 15} gives the same
// per-frame average as 450 frames in a 30th of the time.
BENCHMARK(BM_Alg1PerFrame)
    ->Args({50000, 15})
    ->Args({50000, 450})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_Alg2PerFrame)
    ->Args({50000, 15})
    ->Args({50000, 450})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_MotionFieldEvaluate)
    ->Arg(1000)
    ->Arg(50000)
    ->Unit(benchmark::kMillisecond);
// 2000 points: the dynamic Gaussians of the driver's 320x240 run.
BENCHMARK(BM_MotionFieldEvaluateBackward)
    ->ArgsProduct({{2000, 50000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ResidualFieldEvaluateBackward)
    ->ArgsProduct({{2000, 50000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Alg1ForwardBackward)
    ->ArgsProduct({{2000, 50000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace es

int main(int argc, char** argv) { return es::RunBenchmarks(argc, argv); }
