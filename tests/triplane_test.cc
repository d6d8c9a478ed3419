#include "core/fields/triplane.h"

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/central_differences.h"
#include "tests/plane_combination_name.h"
#include "tests/small_fields.h"

namespace es {
namespace {

using central_differences::ExpectRelativeNear;
using central_differences::NumericDerivative;

Triplane MakeTriplane(PlaneCombination combination) {
  Triplane triplane(SmallPlanes(combination));
  triplane.SetBox(Eigen::Vector3d(-1.0, 0.0, 2.0),
                  Eigen::Vector3d(2.0, 1.0, 4.0));
  return triplane;
}

// Points mostly inside the box, some outside along one or more axes.
std::vector<double> RandomPoints(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.5, 2.5), uy(-0.2, 1.2),
      uz(1.7, 4.3);
  std::vector<double> x(3 * n);
  for (int i = 0; i < n; ++i) {
    x[3 * i] = ux(rng);
    x[3 * i + 1] = uy(rng);
    x[3 * i + 2] = uz(rng);
  }
  return x;
}

class TriplaneGradientTest : public ::testing::TestWithParam<PlaneCombination> {
};

TEST_P(TriplaneGradientTest, MatchesCentralDifferences) {
  const Triplane triplane = MakeTriplane(GetParam());
  std::vector<double> params(triplane.num_params());
  triplane.Initialize(3, params.data());
  const int n = 12;
  std::vector<double> x = RandomPoints(n, 4);
  const int d = triplane.output_dim();
  std::vector<double> weights(n * d);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double& w : weights) w = uniform(rng);

  std::vector<double> out(n * d);
  auto loss = [&]() {
    triplane.Sample(params.data(), n, x.data(), out.data());
    double sum = 0.0;
    for (int i = 0; i < n * d; ++i) sum += weights[i] * out[i];
    return sum;
  };
  std::vector<double> d_params(params.size(), 0.0), d_x(3 * n, 0.0);
  triplane.Backward(params.data(), n, x.data(), weights.data(), d_params.data(),
                    d_x.data());

  int touched = 0;
  for (size_t i = 0; i < params.size(); ++i) {
    ExpectRelativeNear(d_params[i], NumericDerivative(loss, &params[i]),
                       "d_params", i);
    touched += d_params[i] != 0.0;
  }
  EXPECT_GT(touched, 0);
  EXPECT_LE(touched, n * 3 * 4 * triplane.options().channels);
  for (int i = 0; i < 3 * n; ++i) {
    ExpectRelativeNear(d_x[i], NumericDerivative(loss, &x[i]), "d_x", i);
  }

  // The position-only path (parallel) agrees with the combined one.
  std::vector<double> d_x_only(3 * n, 0.0);
  triplane.Backward(params.data(), n, x.data(), weights.data(), nullptr,
                    d_x_only.data());
  for (int i = 0; i < 3 * n; ++i) EXPECT_DOUBLE_EQ(d_x_only[i], d_x[i]);
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, TriplaneGradientTest,
                         AllPlaneCombinations(), CombinationName);

TEST(TriplaneTest, LargeBatchesAccumulateLikeSmallOnes) {
  // Above the parallel threshold each thread has its own gradient buffer.
  const Triplane triplane = MakeTriplane(PlaneCombination::kProduct);
  std::vector<double> params(triplane.num_params());
  triplane.Initialize(3, params.data());
  const int n = 6000, chunk = 1000, d = triplane.output_dim();
  const std::vector<double> x = RandomPoints(n, 8);
  std::vector<double> d_out(n * d);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double& g : d_out) g = uniform(rng);
  std::vector<double> whole(params.size(), 0.0), chunked(params.size(), 0.0);
  std::vector<double> d_x_whole(3 * n, 0.0), d_x_chunked(3 * n, 0.0);
  triplane.Backward(params.data(), n, x.data(), d_out.data(), whole.data(),
                    d_x_whole.data());
  for (int i = 0; i < n; i += chunk) {
    triplane.Backward(params.data(), chunk, x.data() + 3 * i,
                      d_out.data() + d * i, chunked.data(),
                      d_x_chunked.data() + 3 * i);
  }
  for (size_t i = 0; i < params.size(); ++i) {
    EXPECT_NEAR(whole[i], chunked[i], 1e-9 * (1.0 + std::abs(chunked[i])));
  }
  for (int i = 0; i < 3 * n; ++i) EXPECT_EQ(d_x_whole[i], d_x_chunked[i]);
}

TEST(TriplaneTest, TexelCentersReturnTexelValues) {
  const Triplane triplane = MakeTriplane(PlaneCombination::kConcat);
  const int r = 8, c = 4;
  std::vector<double> params(triplane.num_params());
  for (size_t i = 0; i < params.size(); ++i) params[i] = i;
  // Texel (col, row) of the xy plane = 3, 5; z lands on texel 6 of xz / yz.
  const Eigen::Vector3d lo(-1.0, 0.0, 2.0), hi(2.0, 1.0, 4.0);
  const int ix = 3, iy = 5, iz = 6;
  const Eigen::Vector3d x =
      lo.array() + (hi - lo).array() * Eigen::Array3d(ix, iy, iz) / (r - 1);
  std::vector<double> out(3 * c);
  triplane.Sample(params.data(), 1, x.data(), out.data());
  const int texel[3][2] = {{ix, iy}, {ix, iz}, {iy, iz}};  // (col, row)
  for (int p = 0; p < 3; ++p) {
    for (int k = 0; k < c; ++k) {
      const int index = ((p * r + texel[p][1]) * r + texel[p][0]) * c + k;
      EXPECT_NEAR(out[p * c + k], params[index], 1e-9) << p << " " << k;
    }
  }
}

TEST(TriplaneTest, ClampsOutsideTheBoxWithZeroPositionGradient) {
  const Triplane triplane = MakeTriplane(PlaneCombination::kSum);
  std::vector<double> params(triplane.num_params());
  triplane.Initialize(7, params.data());
  // x far beyond the max face; y, z inside.
  const double inside[3] = {2.0, 0.3, 3.1};
  const double outside[3] = {50.0, 0.3, 3.1};
  const double not_finite[3] = {NAN, 0.3, 3.1};
  const int c = triplane.output_dim();
  std::vector<double> a(c), b(c), e(c), ones(c, 1.0);
  triplane.Sample(params.data(), 1, inside, a.data());
  triplane.Sample(params.data(), 1, outside, b.data());
  triplane.Sample(params.data(), 1, not_finite, e.data());
  for (int k = 0; k < c; ++k) {
    EXPECT_NEAR(a[k], b[k], 1e-12);
    EXPECT_TRUE(std::isfinite(e[k]));
  }
  double d_x[3] = {0, 0, 0};
  triplane.Backward(params.data(), 1, outside, ones.data(), nullptr, d_x);
  EXPECT_EQ(d_x[0], 0.0);
  EXPECT_NE(d_x[1], 0.0);
  EXPECT_NE(d_x[2], 0.0);
}

TEST(TriplaneTest, ProductInitializationStartsNearOne) {
  const Triplane triplane = MakeTriplane(PlaneCombination::kProduct);
  std::vector<double> params(triplane.num_params());
  triplane.Initialize(1, params.data());
  const std::vector<double> x = RandomPoints(50, 2);
  std::vector<double> out(50 * triplane.output_dim());
  triplane.Sample(params.data(), 50, x.data(), out.data());
  for (double f : out) {
    EXPECT_GT(f, 0.5 * 0.5 * 0.5);
    EXPECT_LT(f, 1.5 * 1.5 * 1.5);
  }
}

TEST(TriplaneTest, TotalVariationGradientMatchesCentralDifferences) {
  const Triplane triplane = MakeTriplane(PlaneCombination::kSum);
  std::vector<double> params(triplane.num_params());
  triplane.Initialize(9, params.data());
  const double weight = 0.3;
  std::vector<double> grad(params.size(), 0.0);
  const double value =
      triplane.TotalVariation(params.data(), weight, grad.data());
  EXPECT_GT(value, 0.0);
  auto loss = [&]() {
    return triplane.TotalVariation(params.data(), weight, nullptr);
  };
  for (size_t i = 0; i < params.size(); ++i) {
    ExpectRelativeNear(grad[i], NumericDerivative(loss, &params[i]), "tv", i);
  }
  std::vector<double> constant(params.size(), 2.0);
  EXPECT_EQ(triplane.TotalVariation(constant.data(), weight, nullptr), 0.0);
}

}  // namespace
}  // namespace es
