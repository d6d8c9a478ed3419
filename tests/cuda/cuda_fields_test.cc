// The device triplane, MLP and motion field against their CPU twins
// (core/fields): values and every gradient (parameters and inputs) on
// random inputs, for each plane combination, MLPs of 0 to 2 hidden layers
// with widths that are not multiples of the tile, a batch longer than one
// block of the weight gradient, points outside the box and non-finite
// positions; gradients accumulate into non-zero arrays as on the CPU.
// Double on both sides, summed in another order: within 1e-10 relative.
// Skips when no CUDA device is present.

#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_mlp.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/fields/cuda/device_triplane.h"
#include "core/fields/motion_field.h"
#include "core/base/cuda/device_buffer.h"
#include "tests/central_differences.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/plane_combination_name.h"
#include "tests/small_fields.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

constexpr double kTolerance = 1e-10;
constexpr double kInf = std::numeric_limits<double>::infinity();
const Eigen::Vector3d kBoxMin = kFieldTestBoxMin;
const Eigen::Vector3d kBoxMax = kFieldTestBoxMax;

// n points spread over twice the box, so some lie outside it, with the
// hard cases in the first rows: NaN, +-Inf, far away, on the upper corner.
std::vector<double> HardPoints(int n, uint32_t seed) {
  std::vector<double> x = Uniform(3 * n, -4.0, 5.0, seed);
  x[0] = std::numeric_limits<double>::quiet_NaN();
  x[4] = kInf;
  x[8] = -kInf;
  x[9] = 1e300;
  for (int j = 0; j < 3; ++j) x[12 + j] = kBoxMax[j];
  return x;
}

class DeviceTriplaneTest
    : public ::testing::TestWithParam<PlaneCombination> {};

TEST_P(DeviceTriplaneTest, SampleAndBackwardMatchCpuTwin) {
  ES_REQUIRE_GPU("CUDA triplane");
  Triplane cpu(SmallPlanes(GetParam(), 5));
  cpu.SetBox(kBoxMin, kBoxMax);
  std::vector<double> params(cpu.num_params());
  cpu.Initialize(3, params.data());
  const int n = 300;
  // Rows wider than the features: the other columns are left alone.
  const int stride = cpu.output_dim() + 3;
  const std::vector<double> x = HardPoints(n, 4);
  const std::vector<double> d_out = Uniform(n * stride, -1.0, 1.0, 5);
  std::vector<double> out(n * stride, 7.0);
  std::vector<double> d_params = Uniform(cpu.num_params(), -1.0, 1.0, 6);
  std::vector<double> d_x = Uniform(3 * n, -1.0, 1.0, 7);

  DeviceTriplane device(cpu);
  DeviceBuffer<double> dev_params, dev_x, dev_out, dev_d_out, dev_d_params,
      dev_d_x;
  dev_params.Upload(params);
  dev_x.Upload(x);
  dev_out.Upload(out);
  dev_d_out.Upload(d_out);
  dev_d_params.Upload(d_params);
  dev_d_x.Upload(d_x);
  device.Sample(dev_params.data(), n, dev_x.data(), dev_out.data(), stride);
  device.Backward(dev_params.data(), n, dev_x.data(), dev_d_out.data(),
                  dev_d_params.data(), dev_d_x.data(), stride);
  cpu.Sample(params.data(), n, x.data(), out.data(), stride);
  cpu.Backward(params.data(), n, x.data(), d_out.data(), d_params.data(),
               d_x.data(), stride);

  ExpectTwinsNear(dev_out.Download(), out, kTolerance, "features");
  ExpectTwinsNear(dev_d_params.Download(), d_params, kTolerance, "d_params");
  ExpectTwinsNear(dev_d_x.Download(), d_x, kTolerance, "d_x");
  // Non-finite and clamped coordinates have no position gradient.
  const std::vector<double> start = Uniform(3 * n, -1.0, 1.0, 7);
  for (int i : {0, 4, 8, 9}) EXPECT_EQ(d_x[i], start[i]) << i;
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, DeviceTriplaneTest,
                         AllPlaneCombinations(), CombinationName);

struct MlpShape {
  int depth, width, batch;
};

class DeviceMlpTest : public ::testing::TestWithParam<MlpShape> {};

TEST_P(DeviceMlpTest, ForwardAndBackwardMatchCpuTwin) {
  ES_REQUIRE_GPU("CUDA MLP");
  const MlpShape shape = GetParam();
  const int in = 7, out = 5, n = shape.batch;
  Mlp cpu(in, shape.width, shape.depth, out);
  // Random biases too, so some hidden units are off for every row.
  const std::vector<double> params = Uniform(cpu.num_params(), -0.8, 0.8, 8);
  const std::vector<double> input = Uniform(n * in, -1.0, 1.0, 9);
  const std::vector<double> d_out = Uniform(n * out, -1.0, 1.0, 10);
  std::vector<double> d_params = Uniform(cpu.num_params(), -1.0, 1.0, 11);
  std::vector<double> d_input = Uniform(n * in, -1.0, 1.0, 12);
  std::vector<double> y(n * out);

  DeviceMlp device(cpu);
  DeviceBuffer<double> dev_params, dev_input, dev_y(n * out), dev_d_out,
      dev_d_params, dev_d_input;
  dev_params.Upload(params);
  dev_input.Upload(input);
  dev_d_out.Upload(d_out);
  dev_d_params.Upload(d_params);
  dev_d_input.Upload(d_input);
  DeviceMlpWorkspace dev_ws;
  device.Forward(dev_params.data(), n, dev_input.data(), dev_y.data(),
                 &dev_ws);
  device.Backward(dev_params.data(), dev_d_out.data(), dev_d_params.data(),
                  dev_d_input.data(), &dev_ws);
  MlpWorkspace ws;
  cpu.Forward(params.data(), n, input.data(), y.data(), &ws);
  cpu.Backward(params.data(), d_out.data(), d_params.data(), d_input.data(),
               &ws);

  ExpectSomeNonZero(y, "output");
  ExpectTwinsNear(dev_y.Download(), y, kTolerance, "output");
  ExpectTwinsNear(dev_d_params.Download(), d_params, kTolerance, "d_params");
  ExpectTwinsNear(dev_d_input.Download(), d_input, kTolerance, "d_input");

  // Parameter gradients only: the same again on top.
  device.Backward(dev_params.data(), dev_d_out.data(), dev_d_params.data(),
                  nullptr, &dev_ws);
  cpu.Backward(params.data(), d_out.data(), d_params.data(), nullptr, &ws);
  ExpectTwinsNear(dev_d_params.Download(), d_params, kTolerance,
                  "d_params, twice");
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, DeviceMlpTest,
    ::testing::Values(MlpShape{0, 1, 33}, MlpShape{1, 20, 70},
                      MlpShape{2, 16, 50}, MlpShape{2, 33, 17},
                      // More rows than one block of the weight gradient.
                      MlpShape{1, 8, 600}),
    [](const auto& info) {
      return "depth" + std::to_string(info.param.depth) + "_width" +
             std::to_string(info.param.width) + "_batch" +
             std::to_string(info.param.batch);
    });

class DeviceMotionFieldTest
    : public ::testing::TestWithParam<PlaneCombination> {};

TEST_P(DeviceMotionFieldTest, EvaluateAndBackwardMatchCpuTwin) {
  ES_REQUIRE_GPU("CUDA motion field");
  MotionField cpu = TestMotionField(SmallPlanes(GetParam(), 5), 24, 13);
  const int n = 64;
  const std::vector<double> x = HardPoints(n, 14);
  const std::vector<double> d_v = Uniform(3 * n, -1.0, 1.0, 15);
  std::vector<double> v(3 * n);
  std::vector<double> d_triplane(cpu.triplane_params().size(), 0.0);
  std::vector<double> d_mlp(cpu.mlp_params().size(), 0.0);
  std::vector<double> d_x = Uniform(3 * n, -1.0, 1.0, 16);

  DeviceMotionField device(cpu);
  DeviceFieldBlocks params, grads;
  params.Upload(cpu.triplane_params(), cpu.mlp_params());
  grads.Zeros(d_triplane.size(), d_mlp.size());
  DeviceBuffer<double> dev_x, dev_v(3 * n), dev_d_v, dev_d_x;
  dev_x.Upload(x);
  dev_d_v.Upload(d_v);
  dev_d_x.Upload(d_x);
  DeviceFieldWorkspace dev_ws;
  device.Evaluate(params.params(), n, dev_x.data(), dev_v.data(), &dev_ws);
  device.Backward(params.params(), dev_d_v.data(), grads.gradients(),
                  dev_d_x.data(), &dev_ws);
  FieldWorkspace ws;
  cpu.Evaluate(cpu.params(), n, x.data(), v.data(), &ws);
  cpu.Backward(cpu.params(), d_v.data(), {d_triplane.data(), d_mlp.data()},
               d_x.data(), &ws);

  EXPECT_EQ(device.output_scale(), cpu.output_scale());
  ExpectSomeNonZero(v, "velocity");
  ExpectSomeNonZero(d_triplane, "d_triplane");
  ExpectTwinsNear(dev_v.Download(), v, kTolerance, "velocity");
  ExpectFieldGradientsNear(grads, d_triplane, d_mlp, kTolerance);
  ExpectTwinsNear(dev_d_x.Download(), d_x, kTolerance, "d_x");

  // The MLP's gradient alone (no triplane, no positions) adds the same.
  device.Backward(params.params(), dev_d_v.data(), {nullptr, grads.mlp.data()},
                  nullptr, &dev_ws);
  cpu.Backward(cpu.params(), d_v.data(), {nullptr, d_mlp.data()}, nullptr,
               &ws);
  ExpectTwinsNear(grads.mlp.Download(), d_mlp, kTolerance, "d_mlp, twice");
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, DeviceMotionFieldTest,
                         AllPlaneCombinations(), CombinationName);

}  // namespace
}  // namespace cuda
}  // namespace es
