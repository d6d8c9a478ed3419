// The device residual field D against its CPU twin, ResidualField: the 52
// outputs (triplane features, encodings of cycle index and cycle number,
// MLP, output scales) and every gradient (triplane, MLP, x0), for each
// plane combination, with negative cycle numbers, points outside the box
// and non-finite positions. Double on both sides, summed in another order
// and with the device's sin and cos: within 1e-10 relative. Skips when no
// CUDA device is present.

#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_residual_field.h"
#include "core/fields/residual_field.h"
#include "core/base/cuda/device_buffer.h"
#include "tests/central_differences.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"
#include "tests/plane_combination_name.h"

namespace es {
namespace cuda {
namespace {

using central_differences::Uniform;

constexpr double kTolerance = 1e-10;

class DeviceResidualFieldTest
    : public ::testing::TestWithParam<PlaneCombination> {};

TEST_P(DeviceResidualFieldTest, EvaluateAndBackwardMatchCpuTwin) {
  ES_REQUIRE_GPU("CUDA residual field");
  ResidualFieldOptions options;
  options.triplane.resolution = 6;
  options.triplane.channels = 3;
  options.triplane.combination = GetParam();
  options.triplane.init_noise = 0.5;
  options.cycle_length = 12;
  options.t_frequencies = 3;
  options.p_frequencies = 2;
  options.max_cycles = 4;
  options.mlp_width = 16;
  options.mlp_depth = 1;
  options.last_layer_init_scale = 1.0;
  options.position_scale = 0.05;
  ResidualField cpu(options);
  cpu.SetBox(Eigen::Vector3d(-1.0, 0.0, -2.0), Eigen::Vector3d(1.0, 2.0, 1.0));
  cpu.Initialize(17);
  const int n = 14;
  std::vector<double> x0 = Uniform(3 * n, -3.0, 3.0, 18);
  x0[1] = std::numeric_limits<double>::quiet_NaN();
  x0[5] = std::numeric_limits<double>::infinity();
  std::mt19937 rng(19);
  std::vector<int> t(n), p(n);
  for (int i = 0; i < n; ++i) {
    t[i] = static_cast<int>(rng() % options.cycle_length);
    p[i] = static_cast<int>(rng() % 7) - 3;
  }
  const std::vector<double> d_out = Uniform(n * kResidualDim, -1, 1, 20);
  std::vector<double> out(n * kResidualDim);
  std::vector<double> d_triplane = Uniform(cpu.triplane().num_params(), -1, 1,
                                           21);
  std::vector<double> d_mlp = Uniform(cpu.mlp().num_params(), -1, 1, 22);
  std::vector<double> d_x0 = Uniform(3 * n, -1, 1, 23);

  DeviceResidualField device(cpu);
  DeviceFieldBlocks params, grads;
  params.Upload(cpu.triplane_params(), cpu.mlp_params());
  grads.Upload(d_triplane, d_mlp);
  DeviceBuffer<double> dev_x0, dev_out(n * kResidualDim), dev_d_out,
      dev_d_x0;
  DeviceBuffer<int> dev_t, dev_p;
  dev_x0.Upload(x0);
  dev_t.Upload(t);
  dev_p.Upload(p);
  dev_d_out.Upload(d_out);
  dev_d_x0.Upload(d_x0);
  DeviceFieldWorkspace dev_ws;
  device.Evaluate(params.params(), n, dev_x0.data(), dev_t.data(),
                  dev_p.data(), dev_out.data(), &dev_ws);
  device.Backward(params.params(), dev_d_out.data(), grads.gradients(),
                  dev_d_x0.data(), &dev_ws);
  FieldWorkspace ws;
  cpu.Evaluate(cpu.params(), n, x0.data(), t.data(), p.data(), out.data(),
               &ws);
  cpu.Backward(cpu.params(), d_out.data(), {d_triplane.data(), d_mlp.data()},
               d_x0.data(), &ws);

  ExpectSomeNonZero(out, "D");
  ExpectTwinsNear(dev_out.Download(), out, kTolerance, "D");
  ExpectFieldGradientsNear(grads, d_triplane, d_mlp, kTolerance);
  ExpectTwinsNear(dev_d_x0.Download(), d_x0, kTolerance, "d_x0");
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, DeviceResidualFieldTest,
                         AllPlaneCombinations(), CombinationName);

}  // namespace
}  // namespace cuda
}  // namespace es
