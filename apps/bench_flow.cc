// Stage 2 benchmarks: optical flow methods (time per frame pair, endpoint
// error against a known flow), pretraining solvers (time against fit error)
// and the Ceres overhead of the scene-flow cost.
//
//   build/bin/bench_flow [--benchmark_filter=Flow]

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <ceres/ceres.h>
#include <opencv2/imgproc.hpp>

#include "apps/common/benchmark_main.h"
#include "core/flow/optical_flow.h"
#include "costs/scene_flow_cost.h"
#include "solvers/train/flow_pretrain.h"
#include "synth/random_texture.h"

namespace es {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr int kMargin = 16;  // border band where warping replicates pixels

// A smooth flow of up to ~4 px: a swirl plus a drift, like water between
// two frames.
cv::Mat SmoothFlow(int width, int height) {
  cv::Mat flow(height, width, CV_32FC2);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double u = 2.0 * x / width - 1, v = 2.0 * y / height - 1;
      flow.at<cv::Vec2f>(y, x) = cv::Vec2f(1.5 + 2.0 * std::sin(2.5 * v),
                                           0.5 - 2.0 * std::sin(2.0 * u));
    }
  }
  return flow;
}

struct FlowPairFixture {
  cv::Mat first, second, truth, interior;
  FlowPairFixture() {
    second = TwoScaleTexture(kWidth, kHeight, 3, 3);
    truth = SmoothFlow(kWidth, kHeight);
    first = WarpByFlow(second, truth);
    interior = cv::Mat(truth.size(), CV_8UC1, cv::Scalar(0));
    interior(cv::Rect(kMargin, kMargin, kWidth - 2 * kMargin,
                      kHeight - 2 * kMargin)) = 255;
  }
};

void BM_OpticalFlowPair(benchmark::State& state, FlowMethod method) {
  static const FlowPairFixture fixture;
  OpticalFlow flow(method);
  FlowPair pair;
  for (auto _ : state) {
    pair = flow.ComputePair(fixture.first, fixture.second);
    benchmark::DoNotOptimize(pair.forward.data);
  }
  state.counters["epe_px"] =
      MeanEndpointError(pair.forward, fixture.truth, fixture.interior);
  state.SetLabel(FlowMethodName(method) + " forward + backward, " +
                 std::to_string(kWidth) + "x" + std::to_string(kHeight));
}

// Pretraining on samples of a known smooth field.
Eigen::Vector3d TrueVelocity(const Eigen::Vector3d& x) {
  return 0.04 * Eigen::Vector3d(std::sin(1.5 * x.y()) + 0.3,
                                -std::sin(1.5 * x.x()),
                                0.5 * std::cos(x.x() + x.y()));
}

const std::vector<SceneFlowSample>& Samples() {
  static const std::vector<SceneFlowSample> samples = [] {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<SceneFlowSample> s(20000);
    for (SceneFlowSample& sample : s) {
      sample.x = Eigen::Vector3d(u(rng), u(rng), u(rng));
      sample.v = TrueVelocity(sample.x);
    }
    return s;
  }();
  return samples;
}

MotionField Field(int resolution, int channels, int width) {
  MotionFieldOptions o;
  o.triplane.resolution = resolution;
  o.triplane.channels = channels;
  o.mlp_width = width;
  MotionField field(o);
  field.SetBox(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  return field;
}

// Arg 0: iterations. Reports the fit RMSE relative to the targets' RMS.
void BM_Pretrain(benchmark::State& state, PretrainSolver solver,
                 int resolution) {
  const bool tiny = solver == PretrainSolver::kLm;
  FlowPretrainReport report;
  for (auto _ : state) {
    MotionField field = tiny ? Field(4, 3, 8) : Field(resolution, 12, 64);
    FlowPretrainOptions options;
    options.solver = solver;
    options.iterations = static_cast<int>(state.range(0));
    options.batch_size = tiny ? 300 : 4096;
    report = PretrainMotionField(Samples(), options, &field);
  }
  state.counters["fit_rel"] = report.fit_rmse / report.target_rms;
  state.counters["fit_rmse"] = report.fit_rmse;
  state.SetLabel(PretrainSolverName(solver) +
                 (tiny ? " tiny field 4^2x3, MLP 8"
                       : " field " + std::to_string(resolution) +
                             "^2x12, MLP 64x2"));
}

// The Ceres overhead of the scene-flow cost on the paper-size field
// (128^2 x 12 planes, 64 x 2 MLP; ~0.6M parameters) and a batch of 4096.
struct CostFixture {
  MotionField field = Field(128, 12, 64);
  SceneFlowBatch batch;
  CostFixture() {
    std::vector<int> first(4096);
    for (int i = 0; i < 4096; ++i) first[i] = i;
    batch.Assign(Samples(), first);
  }
};

void BM_SceneFlowCostDirect(benchmark::State& state) {
  static CostFixture f;
  const SceneFlowCost cost(&f.field, &f.batch);
  std::vector<double> j_tri(f.field.triplane().num_params());
  std::vector<double> j_mlp(f.field.mlp().num_params());
  const double* params[2] = {f.field.params().triplane, f.field.params().mlp};
  double* jacobians[2] = {j_tri.data(), j_mlp.data()};
  double residual;
  for (auto _ : state) {
    cost.Evaluate(params, &residual, jacobians);
    benchmark::DoNotOptimize(residual);
  }
}

void BM_SceneFlowCostProblemEvaluate(benchmark::State& state) {
  static CostFixture f;
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(options);
  SceneFlowCost cost(&f.field, &f.batch);
  problem.AddResidualBlock(&cost, nullptr, f.field.triplane_params().data(),
                           f.field.mlp_params().data());
  std::vector<double> gradient;
  double value;
  for (auto _ : state) {
    problem.Evaluate(ceres::Problem::EvaluateOptions(), &value, nullptr,
                     &gradient, nullptr);
    benchmark::DoNotOptimize(value);
  }
}

void RegisterAll() {
  for (FlowMethod m : AvailableFlowMethods()) {
    benchmark::RegisterBenchmark(("BM_OpticalFlowPair/" + FlowMethodName(m))
                                     .c_str(),
                                 BM_OpticalFlowPair, m)
        ->Unit(benchmark::kMillisecond);
  }
  for (PretrainSolver s : {PretrainSolver::kAdam, PretrainSolver::kLbfgs}) {
    for (int resolution : {32, 128}) {
      auto* b = benchmark::RegisterBenchmark(
          ("BM_Pretrain/" + PretrainSolverName(s) + "/res" +
           std::to_string(resolution))
              .c_str(),
          BM_Pretrain, s, resolution);
      b->Arg(100)->Arg(300)->Iterations(1)->Unit(benchmark::kSecond);
      // LBFGS evaluates all 20k samples several times per iteration.
      if (s == PretrainSolver::kAdam) b->Arg(1000);
    }
  }
  benchmark::RegisterBenchmark("BM_Pretrain/lm/tiny", BM_Pretrain,
                               PretrainSolver::kLm, 4)
      ->Arg(20)
      ->Arg(50)
      ->Iterations(1)
      ->Unit(benchmark::kSecond);
  benchmark::RegisterBenchmark("BM_SceneFlowCostDirect",
                               BM_SceneFlowCostDirect)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_SceneFlowCostProblemEvaluate",
                               BM_SceneFlowCostProblemEvaluate)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  es::RegisterAll();
  return es::RunBenchmarks(argc, argv);
}
