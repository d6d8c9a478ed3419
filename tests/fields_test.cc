#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/loop/cycle_time.h"
#include "tests/central_differences.h"
#include "tests/plane_combination_name.h"
#include "tests/small_fields.h"

namespace es {
namespace {

using central_differences::ExpectGradientsNear;
using central_differences::Uniform;

const Eigen::Vector3d kBoxMin = kFieldTestBoxMin;
const Eigen::Vector3d kBoxMax = kFieldTestBoxMax;

class MotionFieldGradientTest
    : public ::testing::TestWithParam<PlaneCombination> {};

TEST_P(MotionFieldGradientTest, MatchesCentralDifferences) {
  MotionField field = TestMotionField(SmallPlanes(GetParam()), 16, 21);
  const int n = 10;
  std::vector<double> x = Uniform(3 * n, -1.5, 2.5, 22);
  const std::vector<double> weights = Uniform(3 * n, -1.0, 1.0, 23);

  FieldWorkspace ws;
  std::vector<double> v(3 * n);
  auto loss = [&]() {
    field.Evaluate(field.params(), n, x.data(), v.data(), &ws);
    double sum = 0.0;
    for (int i = 0; i < 3 * n; ++i) sum += weights[i] * v[i];
    return sum;
  };
  loss();
  std::vector<double> d_triplane(field.triplane_params().size(), 0.0);
  std::vector<double> d_mlp(field.mlp_params().size(), 0.0);
  std::vector<double> d_x(3 * n, 0.0);
  field.Backward(field.params(), weights.data(),
                 {d_triplane.data(), d_mlp.data()}, d_x.data(), &ws);
  ExpectGradientsNear(d_triplane, loss, &field.triplane_params(), "triplane");
  ExpectGradientsNear(d_mlp, loss, &field.mlp_params(), "mlp");
  ExpectGradientsNear(d_x, loss, &x, "x");
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, MotionFieldGradientTest,
                         AllPlaneCombinations(), CombinationName);

TEST(MotionFieldTest, DefaultFieldStartsNearlyStill) {
  MotionField field{MotionFieldOptions()};
  EXPECT_EQ(field.triplane_params().size(), 3u * 128 * 128 * 12);
  EXPECT_EQ(field.mlp().input_dim(), 12);
  field.SetBox(kBoxMin, kBoxMax);
  const int n = 100;
  const std::vector<double> x = Uniform(3 * n, -1.0, 1.0, 1);
  std::vector<double> v(3 * n);
  FieldWorkspace ws;
  field.Evaluate(field.params(), n, x.data(), v.data(), &ws);
  // Well under a percent of the box diagonal per frame.
  for (double c : v) EXPECT_LT(std::abs(c), 1e-3 * field.box_diagonal());
}

TEST(MotionFieldTest, OutputScalesWithTheBox) {
  MotionFieldOptions options;
  options.triplane = SmallPlanes(PlaneCombination::kProduct);
  options.mlp_width = 16;
  MotionField small(options), large(options);
  small.SetBox(kBoxMin, kBoxMax);
  large.SetBox(10.0 * kBoxMin, 10.0 * kBoxMax);
  const double x_small[3] = {0.3, 0.2, 1.0};
  const double x_large[3] = {3.0, 2.0, 10.0};
  double v_small[3], v_large[3];
  FieldWorkspace ws;
  small.Evaluate(small.params(), 1, x_small, v_small, &ws);
  large.Evaluate(large.params(), 1, x_large, v_large, &ws);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(v_large[j], 10.0 * v_small[j], 1e-12);
}

// A small residual field whose outputs are far from zero.
ResidualFieldOptions SmallResidual(PlaneCombination combination) {
  ResidualFieldOptions options;
  options.triplane = SmallPlanes(combination);
  options.mlp_width = 16;
  options.last_layer_init_scale = 1.0;
  return options;
}

TEST(ResidualFieldTest, GradientsMatchCentralDifferences) {
  ResidualFieldOptions options = SmallResidual(PlaneCombination::kProduct);
  options.position_scale = 0.2;
  ResidualField field(options);
  field.SetBox(kBoxMin, kBoxMax);
  field.Initialize(31);
  const int n = 8;
  std::vector<double> x0 = Uniform(3 * n, -1.5, 2.5, 32);
  const std::vector<int> t = {0, 3, 14, 7, 7, 1, 9, 12};
  const std::vector<int> p = {0, -1, 2, 0, 1, -2, 5, 0};
  const std::vector<double> weights = Uniform(kResidualDim * n, -1.0, 1.0, 33);

  FieldWorkspace ws;
  std::vector<double> out(kResidualDim * n);
  auto loss = [&]() {
    field.Evaluate(field.params(), n, x0.data(), t.data(), p.data(), out.data(),
                   &ws);
    double sum = 0.0;
    for (int i = 0; i < kResidualDim * n; ++i) sum += weights[i] * out[i];
    return sum;
  };
  loss();
  std::vector<double> d_triplane(field.triplane_params().size(), 0.0);
  std::vector<double> d_mlp(field.mlp_params().size(), 0.0);
  std::vector<double> d_x0(3 * n, 0.0);
  field.Backward(field.params(), weights.data(),
                 {d_triplane.data(), d_mlp.data()}, d_x0.data(), &ws);
  ExpectGradientsNear(d_triplane, loss, &field.triplane_params(), "triplane");
  ExpectGradientsNear(d_mlp, loss, &field.mlp_params(), "mlp");
  ExpectGradientsNear(d_x0, loss, &x0, "x0");
}

TEST(ResidualFieldTest, DependsOnCycleIndexAndNumber) {
  ResidualField field(SmallResidual(PlaneCombination::kSum));
  EXPECT_EQ(field.mlp().input_dim(), 4 + 8 + 8);
  const double x0[9] = {0.1, 0.2, 0.3, 0.1, 0.2, 0.3, 0.1, 0.2, 0.3};
  const int t[3] = {2, 3, 2};
  const int p[3] = {0, 0, 1};
  std::vector<double> out(3 * kResidualDim);
  FieldWorkspace ws;
  field.Evaluate(field.params(), 3, x0, t, p, out.data(), &ws);
  double dt = 0.0, dp = 0.0;
  for (int k = 0; k < kResidualDim; ++k) {
    dt = std::max(dt, std::abs(out[k] - out[kResidualDim + k]));
    dp = std::max(dp, std::abs(out[k] - out[2 * kResidualDim + k]));
  }
  EXPECT_GT(dt, 1e-6);
  EXPECT_GT(dp, 1e-6);
}

TEST(ResidualFieldTest, WithoutCycleFrequenciesIsPeriodic) {
  // es_train --residual_cycle_frequencies 0: D ignores the cycle number.
  ResidualFieldOptions options = SmallResidual(PlaneCombination::kSum);
  options.p_frequencies = 0;
  ResidualField field(options);
  EXPECT_EQ(field.mlp().input_dim(), 4 + 8);
  const double x0[6] = {0.1, 0.2, 0.3, 0.1, 0.2, 0.3};
  const int t[2] = {2, 2};
  const int p[2] = {0, 3};
  std::vector<double> out(2 * kResidualDim);
  FieldWorkspace ws;
  field.Evaluate(field.params(), 2, x0, t, p, out.data(), &ws);
  for (int k = 0; k < kResidualDim; ++k)
    EXPECT_EQ(out[k], out[kResidualDim + k]);
}

TEST(ResidualFieldTest, DefaultFieldStartsNearZero) {
  ResidualField field{ResidualFieldOptions()};
  EXPECT_EQ(field.mlp().input_dim(), 16 + 8 + 8);
  EXPECT_EQ(field.mlp().output_dim(), kResidualDim);
  const double x0[3] = {0.1, -0.2, 0.3};
  const int t = 4, p = 1;
  std::vector<double> out(kResidualDim);
  FieldWorkspace ws;
  field.Evaluate(field.params(), 1, x0, &t, &p, out.data(), &ws);
  for (double c : out) EXPECT_LT(std::abs(c), 0.05);
}

}  // namespace
}  // namespace es
