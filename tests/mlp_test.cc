#include "core/fields/mlp.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/central_differences.h"

namespace es {
namespace {

using central_differences::ExpectRelativeNear;
using central_differences::NumericDerivative;
using central_differences::Uniform;

class MlpGradientTest : public ::testing::TestWithParam<int> {};

TEST_P(MlpGradientTest, MatchesCentralDifferences) {
  const int depth = GetParam();
  const Mlp mlp(5, 16, depth, 3);
  std::vector<double> params(mlp.num_params());
  mlp.Initialize(11, 1.0, params.data());
  // Non-zero biases so their gradients are exercised off the origin.
  const std::vector<double> noise = Uniform(mlp.num_params(), -1.0, 1.0, 12);
  for (size_t i = 0; i < params.size(); ++i) params[i] += 0.1 * noise[i];
  const int n = 7;
  std::vector<double> input = Uniform(n * 5, -1.0, 1.0, 13);
  const std::vector<double> weights = Uniform(n * 3, -1.0, 1.0, 14);

  MlpWorkspace ws;
  std::vector<double> out(n * 3);
  auto loss = [&]() {
    mlp.Forward(params.data(), n, input.data(), out.data(), &ws);
    double sum = 0.0;
    for (int i = 0; i < n * 3; ++i) sum += weights[i] * out[i];
    return sum;
  };
  loss();
  std::vector<double> d_params(params.size(), 0.0), d_input(n * 5, 0.0);
  mlp.Backward(params.data(), weights.data(), d_params.data(), d_input.data(),
               &ws);
  for (size_t i = 0; i < params.size(); ++i) {
    ExpectRelativeNear(d_params[i], NumericDerivative(loss, &params[i]),
                       "d_params", i);
  }
  for (int i = 0; i < n * 5; ++i) {
    ExpectRelativeNear(d_input[i], NumericDerivative(loss, &input[i]),
                       "d_input", i);
  }
}

INSTANTIATE_TEST_SUITE_P(Depths, MlpGradientTest, ::testing::Values(0, 1, 2));

TEST(MlpTest, LargeBatchesMatchSmallBatches) {
  // Large batches are cut into chunks run in parallel with per-thread
  // gradient buffers; the result must not depend on that.
  const Mlp mlp(6, 16, 2, 4);
  std::vector<double> params(mlp.num_params());
  mlp.Initialize(21, 1.0, params.data());
  const int n = 2000, part = 100;
  const std::vector<double> input = Uniform(n * 6, -1.0, 1.0, 22);
  const std::vector<double> d_out = Uniform(n * 4, -1.0, 1.0, 23);
  MlpWorkspace ws;
  std::vector<double> out(n * 4), d_params(params.size(), 0.0),
      d_input(n * 6, 0.0);
  mlp.Forward(params.data(), n, input.data(), out.data(), &ws);
  mlp.Backward(params.data(), d_out.data(), d_params.data(), d_input.data(),
               &ws);
  std::vector<double> part_out(part * 4), part_params(params.size(), 0.0),
      part_input(n * 6, 0.0);
  for (int r = 0; r < n; r += part) {
    mlp.Forward(params.data(), part, input.data() + r * 6, part_out.data(),
                &ws);
    for (int i = 0; i < part * 4; ++i) {
      EXPECT_NEAR(part_out[i], out[r * 4 + i], 1e-12);
    }
    mlp.Backward(params.data(), d_out.data() + r * 4, part_params.data(),
                 part_input.data() + r * 6, &ws);
  }
  for (size_t i = 0; i < params.size(); ++i) {
    EXPECT_NEAR(d_params[i], part_params[i],
                1e-10 * (1.0 + std::abs(part_params[i])));
  }
  for (int i = 0; i < n * 6; ++i) {
    EXPECT_NEAR(d_input[i], part_input[i], 1e-12);
  }
}

// Float precision computes what double does to float rounding, in the
// residual field's shape and over several chunks (the parallel path); a
// bug in its conversions or buffers (a wrong offset, a stale chunk) gives
// errors of the values' own size.
TEST(MlpTest, FloatPrecisionMatchesDoubleToFloatRounding) {
  Mlp mlp(32, 128, 2, 52);
  std::vector<double> params(mlp.num_params());
  mlp.Initialize(31, 1.0, params.data());
  const int n = 1300;
  const std::vector<double> input = Uniform(n * 32, -1.0, 1.0, 32);
  const std::vector<double> d_out = Uniform(n * 52, -1.0, 1.0, 33);
  auto run = [&](MlpPrecision precision, std::vector<double>* out,
                 std::vector<double>* d_params, std::vector<double>* d_input) {
    mlp.set_precision(precision);
    MlpWorkspace ws;
    out->assign(n * 52, 0.0);
    // Backward adds: start from ones to check it adds, not overwrites.
    d_params->assign(params.size(), 1.0);
    d_input->assign(n * 32, 1.0);
    mlp.Forward(params.data(), n, input.data(), out->data(), &ws);
    mlp.Backward(params.data(), d_out.data(), d_params->data(),
                 d_input->data(), &ws);
  };
  std::vector<double> out, dp, di, out_f, dp_f, di_f;
  run(MlpPrecision::kDouble, &out, &dp, &di);
  run(MlpPrecision::kFloat, &out_f, &dp_f, &di_f);
  // Relative to each array's largest entry: float's rounding of sums of
  // up to n terms.
  auto expect_near = [](const std::vector<double>& want,
                        const std::vector<double>& got, double tolerance,
                        const char* what) {
    double scale = 0.0;
    for (double v : want) scale = std::max(scale, std::abs(v));
    for (size_t i = 0; i < want.size(); ++i) {
      ASSERT_NEAR(got[i], want[i], tolerance * scale) << what << " " << i;
    }
  };
  expect_near(out, out_f, 1e-5, "output");
  expect_near(dp, dp_f, 1e-4, "d_params");
  expect_near(di, di_f, 1e-5, "d_input");
}

TEST(MlpTest, ParameterLayoutIsWeightsThenBiasPerLayer) {
  const Mlp mlp(2, 3, 1, 1);
  EXPECT_EQ(mlp.num_params(), 3 * 2 + 3 + 1 * 3 + 1);
  // Hidden: W = [[1,0],[0,1],[1,1]], b = [0,0,-10]; output W = [1,2,3], b=0.5
  std::vector<double> params = {1, 0, 0, 1, 1, 1, 0, 0, -10, 1, 2, 3, 0.5};
  MlpWorkspace ws;
  const double input[2] = {2.0, 3.0};
  double out = 0.0;
  mlp.Forward(params.data(), 1, input, &out, &ws);
  // Hidden = relu([2, 3, -5]) = [2, 3, 0]; out = 2 + 6 + 0 + 0.5.
  EXPECT_DOUBLE_EQ(out, 8.5);
}

TEST(MlpTest, SmallLastLayerGivesNearZeroOutput) {
  const Mlp mlp(12, 64, 2, 3);
  std::vector<double> params(mlp.num_params());
  mlp.Initialize(1, 1e-3, params.data());
  const int n = 100;
  const std::vector<double> input = Uniform(n * 12, -1.0, 1.0, 2);
  std::vector<double> out(n * 3);
  MlpWorkspace ws;
  mlp.Forward(params.data(), n, input.data(), out.data(), &ws);
  for (double v : out) EXPECT_LT(std::abs(v), 0.05);
}

TEST(MlpTest, WorkspaceIsReusedAtTheSameOrASmallerBatchSize) {
  const Mlp mlp(4, 8, 2, 3);
  std::vector<double> params(mlp.num_params());
  mlp.Initialize(1, 1.0, params.data());
  const int n = 9;
  const std::vector<double> input = Uniform(n * 4, -1.0, 1.0, 3);
  const std::vector<double> d_out = Uniform(n * 3, -1.0, 1.0, 4);
  std::vector<double> out(n * 3), d_params(params.size());
  MlpWorkspace ws;
  mlp.Forward(params.data(), n, input.data(), out.data(), &ws);
  mlp.Backward(params.data(), d_out.data(), d_params.data(), nullptr, &ws);
  const double* hidden = ws.f64.hidden[0].data();
  const double* grad = ws.f64.grad.data();
  const double* grad_prev = ws.f64.grad_prev.data();
  // The Euler chain's batches shrink step by step: no reallocation then.
  for (const int batch : {n, n, n - 4, 1}) {
    mlp.Forward(params.data(), batch, input.data(), out.data(), &ws);
    mlp.Backward(params.data(), d_out.data(), d_params.data(), nullptr, &ws);
  }
  EXPECT_EQ(ws.f64.hidden[0].data(), hidden);
  EXPECT_EQ(ws.f64.grad.data(), grad);
  EXPECT_EQ(ws.f64.grad_prev.data(), grad_prev);
}

}  // namespace
}  // namespace es
