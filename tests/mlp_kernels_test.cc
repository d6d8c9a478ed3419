#include "core/fields/mlp_kernels.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/mlp.h"
#include "tests/central_differences.h"
#include "tests/per_simd_level_test.h"

namespace es {
namespace {

using central_differences::Uniform;

class MlpKernelLevelTest : public PerSimdLevelTest {};

// Shapes with every kind of remainder: rows not a multiple of the row
// tile, columns below, at and past the widest column tile, single rows and
// columns.
struct Shape {
  int rows, k, n;
};
const Shape kShapes[] = {{1, 1, 1},   {3, 5, 3},    {4, 12, 64},
                         {7, 64, 3},  {9, 64, 64},  {13, 32, 128},
                         {5, 128, 52}, {17, 19, 23}, {2, 3, 100}};

// Uniform values in [-1, 1] as T.
template <typename T>
std::vector<T> Values(int size, int seed) {
  const std::vector<double> v = Uniform(size, -1.0, 1.0, seed);
  return std::vector<T>(v.begin(), v.end());
}

// A multiply kernel in T against its definition summed in double, within
// `tolerance` per term of the sum.
template <typename T>
void ExpectMultiplyMatches(void (*multiply)(int, int, int, const T*, const T*,
                                            const T*, bool, T*),
                           double tolerance, int seed) {
  for (const Shape& s : kShapes) {
    const std::vector<T> a = Values<T>(s.rows * s.k, seed++);
    const std::vector<T> b = Values<T>(s.k * s.n, seed++);
    const std::vector<T> bias = Values<T>(s.n, seed++);
    const std::vector<T> start = Values<T>(s.rows * s.n, seed++);
    for (const bool accumulate : {false, true}) {
      for (const bool with_bias : {false, true}) {
        std::vector<T> c = start;
        multiply(s.rows, s.k, s.n, a.data(), b.data(),
                 with_bias ? bias.data() : nullptr, accumulate, c.data());
        for (int r = 0; r < s.rows; ++r) {
          for (int j = 0; j < s.n; ++j) {
            double want = accumulate ? start[r * s.n + j]
                                     : (with_bias ? bias[j] : 0.0);
            for (int p = 0; p < s.k; ++p)
              want += double(a[r * s.k + p]) * b[p * s.n + j];
            ASSERT_NEAR(c[r * s.n + j], want, tolerance * (1 + s.k))
                << s.rows << "x" << s.k << "x" << s.n << " at " << r << ","
                << j << (accumulate ? " accumulate" : "")
                << (with_bias ? " bias" : "");
          }
        }
      }
    }
  }
}

// c (m x n) += a^T b for a (rows x m) and b (rows x n), as above.
template <typename T>
void ExpectMultiplyTransposedMatches(
    void (*multiply_transposed)(int, int, int, const T*, const T*, T*),
    double tolerance, int seed) {
  for (const Shape& s : kShapes) {
    const std::vector<T> a = Values<T>(s.rows * s.k, seed++);  // m = s.k
    const std::vector<T> b = Values<T>(s.rows * s.n, seed++);
    const std::vector<T> start = Values<T>(s.k * s.n, seed++);
    std::vector<T> c = start;
    multiply_transposed(s.rows, s.k, s.n, a.data(), b.data(), c.data());
    for (int i = 0; i < s.k; ++i) {
      for (int j = 0; j < s.n; ++j) {
        double want = start[i * s.n + j];
        for (int r = 0; r < s.rows; ++r)
          want += double(a[r * s.k + i]) * b[r * s.n + j];
        ASSERT_NEAR(c[i * s.n + j], want, tolerance * (1 + s.rows))
            << s.rows << "x" << s.k << "x" << s.n << " at " << i << "," << j;
      }
    }
  }
}

// Double within 1e-13 per term, float within its rounding (2e-7).
TEST_P(MlpKernelLevelTest, MultiplyMatchesTheDefinition) {
  const MlpKernelSet& kernels = MlpKernels(GetParam());
  ExpectMultiplyMatches<double>(kernels.multiply, 1e-13, 1);
  ExpectMultiplyMatches<float>(kernels.multiply_float, 2e-7, 1);
}

TEST_P(MlpKernelLevelTest, MultiplyTransposedMatchesTheDefinition) {
  const MlpKernelSet& kernels = MlpKernels(GetParam());
  ExpectMultiplyTransposedMatches<double>(kernels.multiply_transposed, 1e-13,
                                          100);
  ExpectMultiplyTransposedMatches<float>(kernels.multiply_transposed_float,
                                         2e-7, 100);
}

// The whole network, forward and backward, at this level against SSE2, in
// the motion and residual fields' shapes (the gradient itself is checked
// against central differences in mlp_test.cc).
TEST_P(MlpKernelLevelTest, NetworkMatchesSse2ToRounding) {
  struct Net {
    int in, width, depth, out;
  };
  for (const Net& net : {Net{12, 64, 2, 3}, Net{32, 128, 2, 52}}) {
    Mlp mlp(net.in, net.width, net.depth, net.out);
    std::vector<double> params(mlp.num_params());
    mlp.Initialize(3, 1.0, params.data());
    const int n = 700;  // two chunks: the parallel path too
    const std::vector<double> input = Uniform(n * net.in, -1.0, 1.0, 4);
    const std::vector<double> d_out = Uniform(n * net.out, -1.0, 1.0, 5);
    auto run = [&](SimdLevel level, std::vector<double>* out,
                   std::vector<double>* d_params,
                   std::vector<double>* d_input) {
      mlp.set_simd_level(level);
      MlpWorkspace ws;
      out->assign(n * net.out, 0.0);
      d_params->assign(params.size(), 0.0);
      d_input->assign(n * net.in, 0.0);
      mlp.Forward(params.data(), n, input.data(), out->data(), &ws);
      mlp.Backward(params.data(), d_out.data(), d_params->data(),
                   d_input->data(), &ws);
    };
    std::vector<double> out0, dp0, di0, out1, dp1, di1;
    run(SimdLevel::kSse2, &out0, &dp0, &di0);
    run(GetParam(), &out1, &dp1, &di1);
    auto expect_near = [](const std::vector<double>& want,
                          const std::vector<double>& got, const char* what) {
      ASSERT_EQ(want.size(), got.size());
      for (size_t i = 0; i < want.size(); ++i) {
        ASSERT_NEAR(got[i], want[i], 1e-11 * (1 + std::abs(want[i])))
            << what << " " << i;
      }
    };
    expect_near(out0, out1, "output");
    expect_near(dp0, dp1, "d_params");
    expect_near(di0, di1, "d_input");
  }
}

INSTANTIATE_TEST_SUITE_P(Levels, MlpKernelLevelTest, AllSimdLevels(),
                         SimdLevelTestName);

}  // namespace
}  // namespace es
