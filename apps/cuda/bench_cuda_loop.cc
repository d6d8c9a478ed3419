// Google Benchmark of the looping model on the device (core/fields/cuda,
// core/loop/cuda): Alg. 2's frame (one Euler step of V for every dynamic
// Gaussian, D at p = 0, composition, render) as DeviceLoopRenderer plays
// a model, and the training-side pieces: V's evaluate + backward and
// Alg. 1's chain forward + backward over a cycle.
//
//   build/bin/bench_cuda_loop --benchmark_counters_tabular=true
//
// The scene is bench_cuda_rasterizer's (apps/common/raster_bench_scene.h):
// 1168x880, 300k Gaussians, every third of them dynamic (100k), with V and
// D at their default sizes (128^2 planes; MLPs 64 x 2 and 128 x 2) over
// the dynamic Gaussians' box, L = 15. Each iteration ends when the device
// is done. Prints why and exits with status 0 when no CUDA device is
// present.

#include <cstdio>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "apps/common/raster_bench_scene.h"
#include "apps/cuda/cuda_benchmark_main.h"
#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/loop/cuda/device_euler_chain.h"
#include "core/loop/cuda/device_loop_renderer.h"
#include "core/loop/cycle_time.h"
#include "core/loop/loop_model.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 15;

// The rasterizer benchmark's scene as a looping model.
LoopModel MakeLoopModel(const BenchScene& scene) {
  LoopModel m;
  m.gaussians = scene.gaussians;
  m.cycle_length = kCycle;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int n = 0; n < m.gaussians.size(); n += 3) {
    m.dynamic_index.push_back(n);
    const Eigen::Vector3d x(&m.gaussians.means[3 * n]);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  m.start_times = RandomStartTimes(m.num_dynamic(), kCycle, 3);
  m.motion.emplace(MotionFieldOptions());
  m.motion->SetBox(lo, hi);
  ResidualFieldOptions residual;
  residual.cycle_length = kCycle;
  m.residual.emplace(residual);
  m.residual->SetBox(lo, hi);
  return m;
}

const BenchScene& Scene() {
  static const BenchScene scene = MakeScene(1168, 880, 300000);
  return scene;
}

void BM_CudaAlg2Frame(benchmark::State& state) {
  const LoopModel model = MakeLoopModel(Scene());
  DeviceLoopRenderer renderer(&model);
  renderer.Start(0);
  const Eigen::Vector3d background(0, 0, 0);
  // One untimed frame: buffers are allocated once.
  renderer.Advance();
  renderer.Render(Scene().camera, background);
  float sink = 0;
  for (auto _ : state) {
    renderer.Advance();
    const DeviceImages& images = renderer.Render(Scene().camera, background);
    CopyToHost(&sink, images.rgb, sizeof(sink));  // waits for the device
  }
  benchmark::DoNotOptimize(sink);
  state.counters["dynamic"] = model.num_dynamic();
}

// What the V benchmarks start from: the dynamic Gaussians' canonical
// positions and V on the device, its parameters uploaded and its gradient
// blocks zeroed.
struct MotionFieldBench {
  LoopModel model = MakeLoopModel(Scene());
  DeviceBuffer<double> x0;
  DeviceMotionField device{*model.motion};
  DeviceFieldBlocks params, grads;
  MotionFieldBench() {
    std::vector<double> x;
    for (int g : model.dynamic_index) {
      for (int j = 0; j < 3; ++j) x.push_back(model.gaussians.means[3 * g + j]);
    }
    x0.Upload(x);
    const MotionField& field = *model.motion;
    params.Upload(field.params(), field.triplane().num_params(),
                  field.mlp().num_params());
    grads.Zeros(field.triplane().num_params(), field.mlp().num_params());
  }
  int n() const { return model.num_dynamic(); }
};

void BM_CudaMotionFieldEvaluateBackward(benchmark::State& state) {
  MotionFieldBench p;
  DeviceBuffer<double> v(3 * p.n()), d_x(3 * p.n());
  d_x.Zero();
  DeviceFieldWorkspace ws;
  double sink = 0;
  for (auto _ : state) {
    p.device.Evaluate(p.params.params(), p.n(), p.x0.data(), v.data(), &ws);
    // d loss / d v = v: any dense gradient does.
    p.device.Backward(p.params.params(), v.data(), p.grads.gradients(),
                      d_x.data(), &ws);
    CopyToHost(&sink, d_x.data(), sizeof(sink));
  }
  benchmark::DoNotOptimize(sink);
  state.counters["points"] = p.n();
}

// One training frame of Alg. 1: every dynamic Gaussian advected to its
// cycle index and back.
void BM_CudaAlg1ForwardBackward(benchmark::State& state) {
  MotionFieldBench p;
  DeviceEulerChain chain(&p.device, EulerOptions());
  std::vector<int> steps(p.n());
  for (int k = 0; k < p.n(); ++k) {
    steps[k] = CycleIndex(kCycle - 1, p.model.start_times[k], kCycle);
  }
  DeviceBuffer<double> x(3 * p.n()), d_x0(3 * p.n());
  d_x0.Zero();
  double sink = 0;
  for (auto _ : state) {
    chain.Forward(p.params.params(), p.n(), p.x0.data(), steps.data(),
                  x.data());
    chain.Backward(p.params.params(), x.data(), p.grads.gradients(),
                   d_x0.data());
    CopyToHost(&sink, d_x0.data(), sizeof(sink));
  }
  benchmark::DoNotOptimize(sink);
  state.counters["evaluations"] =
      static_cast<double>(chain.stats().velocity_evaluations);
}

BENCHMARK(BM_CudaAlg2Frame)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CudaMotionFieldEvaluateBackward)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_CudaAlg1ForwardBackward)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace cuda
}  // namespace es

ES_CUDA_BENCHMARK_MAIN("bench_cuda_loop")
