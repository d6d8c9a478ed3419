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

TEST_P(MlpKernelLevelTest, MultiplyMatchesTheDefinition) {
  const MlpKernelSet& kernels = MlpKernels(GetParam());
  int seed = 1;
  for (const Shape& s : kShapes) {
    const std::vector<double> a = Uniform(s.rows * s.k, -1.0, 1.0, seed++);
    const std::vector<double> b = Uniform(s.k * s.n, -1.0, 1.0, seed++);
    const std::vector<double> bias = Uniform(s.n, -1.0, 1.0, seed++);
    const std::vector<double> start = Uniform(s.rows * s.n, -1, 1, seed++);
    for (const bool accumulate : {false, true}) {
      for (const bool with_bias : {false, true}) {
        std::vector<double> c = start;
        kernels.multiply(s.rows, s.k, s.n, a.data(), b.data(),
                         with_bias ? bias.data() : nullptr, accumulate,
                         c.data());
        for (int r = 0; r < s.rows; ++r) {
          for (int j = 0; j < s.n; ++j) {
            double want = accumulate ? start[r * s.n + j]
                                     : (with_bias ? bias[j] : 0.0);
            for (int p = 0; p < s.k; ++p)
              want += a[r * s.k + p] * b[p * s.n + j];
            ASSERT_NEAR(c[r * s.n + j], want, 1e-13 * (1 + s.k))
                << s.rows << "x" << s.k << "x" << s.n << " at " << r << ","
                << j << (accumulate ? " accumulate" : "")
                << (with_bias ? " bias" : "");
          }
        }
      }
    }
  }
}

TEST_P(MlpKernelLevelTest, MultiplyTransposedMatchesTheDefinition) {
  const MlpKernelSet& kernels = MlpKernels(GetParam());
  int seed = 100;
  for (const Shape& s : kShapes) {
    // a is rows x m (m = s.k), b rows x n; c (m x n) += a^T b.
    const std::vector<double> a = Uniform(s.rows * s.k, -1.0, 1.0, seed++);
    const std::vector<double> b = Uniform(s.rows * s.n, -1.0, 1.0, seed++);
    const std::vector<double> start = Uniform(s.k * s.n, -1, 1, seed++);
    std::vector<double> c = start;
    kernels.multiply_transposed(s.rows, s.k, s.n, a.data(), b.data(),
                                c.data());
    for (int i = 0; i < s.k; ++i) {
      for (int j = 0; j < s.n; ++j) {
        double want = start[i * s.n + j];
        for (int r = 0; r < s.rows; ++r)
          want += a[r * s.k + i] * b[r * s.n + j];
        ASSERT_NEAR(c[i * s.n + j], want, 1e-13 * (1 + s.rows))
            << s.rows << "x" << s.k << "x" << s.n << " at " << i << "," << j;
      }
    }
  }
}

// The float products against the definition summed in double: within
// float rounding of the sum's terms.
TEST_P(MlpKernelLevelTest, FloatProductsMatchTheDefinition) {
  const MlpKernelSet& kernels = MlpKernels(GetParam());
  int seed = 200;
  auto floats = [&seed](int size) {
    const std::vector<double> v = Uniform(size, -1.0, 1.0, seed++);
    return std::vector<float>(v.begin(), v.end());
  };
  for (const Shape& s : kShapes) {
    const std::vector<float> a = floats(s.rows * s.k);
    const std::vector<float> b = floats(s.k * s.n);
    const std::vector<float> bias = floats(s.n);
    std::vector<float> c(s.rows * s.n, 7.0f);
    kernels.multiply_float(s.rows, s.k, s.n, a.data(), b.data(), bias.data(),
                           /*accumulate=*/false, c.data());
    for (int r = 0; r < s.rows; ++r) {
      for (int j = 0; j < s.n; ++j) {
        double want = bias[j];
        for (int p = 0; p < s.k; ++p)
          want += double(a[r * s.k + p]) * b[p * s.n + j];
        ASSERT_NEAR(c[r * s.n + j], want, 2e-7 * (1 + s.k))
            << s.rows << "x" << s.k << "x" << s.n << " at " << r << "," << j;
      }
    }
    // c (k x n) += a^T b2 for b2 rows x n.
    const std::vector<float> b2 = floats(s.rows * s.n);
    const std::vector<float> start = floats(s.k * s.n);
    std::vector<float> ct = start;
    kernels.multiply_transposed_float(s.rows, s.k, s.n, a.data(), b2.data(),
                                      ct.data());
    for (int i = 0; i < s.k; ++i) {
      for (int j = 0; j < s.n; ++j) {
        double want = start[i * s.n + j];
        for (int r = 0; r < s.rows; ++r)
          want += double(a[r * s.k + i]) * b2[r * s.n + j];
        ASSERT_NEAR(ct[i * s.n + j], want, 2e-7 * (1 + s.rows))
            << s.rows << "x" << s.k << "x" << s.n << " at " << i << "," << j;
      }
    }
  }
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
