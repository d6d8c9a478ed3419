// The device loop renderer against its CPU twin, LoopRenderer: the
// composed splats of every frame over more than a cycle (V's Euler step
// per frame, D at p = 0 on positions, opacity and up to 16 SH
// coefficients), for SH degrees below and at D's 16 coefficients and
// models without V or without D; and the rendered frame against the
// device rasterizer's render of the CPU-composed splats. Double on both
// sides: splats within 1e-9 relative. Skips when no CUDA device is
// present.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/loop/cuda/device_loop_renderer.h"
#include "core/loop/loop_renderer.h"
#include "core/model/gaussians.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "tests/centered_camera.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/host_arrays.h"
#include "tests/cuda/require_gpu.h"
#include "tests/cuda/tiny_loop_model.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 4;
constexpr double kTolerance = 1e-9;

class DeviceLoopRendererTest
    : public ::testing::TestWithParam<TinyLoopModelCase> {};

TEST_P(DeviceLoopRendererTest, ComposesAndRendersAsCpuTwin) {
  ES_REQUIRE_GPU("CUDA loop renderer");
  const LoopModel model = TinyLoopModel(GetParam(), kCycle, 0.05);
  LoopRenderer cpu(&model, RenderOptions());
  DeviceLoopRenderer device(&model);
  const int first = 2;
  cpu.Start(first);
  device.Start(first);
  const size_t n = model.gaussians.size();
  const size_t sh = 3 * model.gaussians.sh_coeffs() * n;
  for (int frame = first; frame <= first + kCycle + 1; ++frame) {
    if (frame > first) {
      cpu.Advance();
      device.Advance();
    }
    ASSERT_EQ(device.frame(), frame);
    SCOPED_TRACE("frame " + std::to_string(frame));
    const SplatView& want = cpu.Compose();
    const DeviceSplatView& got = device.Compose();
    ASSERT_EQ(got.count, want.count);
    ASSERT_EQ(got.sh_degree, want.sh_degree);
    ExpectTwinsNear(Fetch(got.means, 3 * n), Copy(want.means, 3 * n),
                    kTolerance, "means");
    ExpectTwinsNear(Fetch(got.opacity_logits, n),
                    Copy(want.opacity_logits, n), kTolerance,
                    "opacity_logits");
    ExpectTwinsNear(Fetch(got.sh, sh), Copy(want.sh, sh), kTolerance, "sh");
    ExpectTwinsNear(Fetch(got.log_scales, 3 * n), Copy(want.log_scales, 3 * n),
                    0, "log_scales");
    const EulerStats a = device.euler_stats(), b = cpu.euler_stats();
    EXPECT_EQ(a.velocity_evaluations, b.velocity_evaluations);
    EXPECT_EQ(a.clamped_steps, b.clamped_steps);
  }

  // The frame itself: the device rasterizer on the CPU-composed splats.
  const Camera camera = CenteredCamera(40, 30, 40);
  const Eigen::Vector3d background(0.1, 0.2, 0.3);
  RenderOptions options;
  options.background = background;
  RenderResult want;
  DeviceRasterizer reference;
  reference.Forward(camera, cpu.Compose(), options, &want);
  const DeviceImages& got = device.Render(camera, background);
  ASSERT_EQ(got.width, camera.width);
  std::vector<float> rgb(3 * camera.width * camera.height);
  CopyToHost(rgb.data(), got.rgb, rgb.size() * sizeof(float));
  ExpectSomeNonZero(std::vector<double>(want.alpha), "alpha");
  ExpectTwinsNear(std::vector<double>(rgb.begin(), rgb.end()), want.rgb, 1e-5,
                  "rgb");
}

INSTANTIATE_TEST_SUITE_P(
    Models, DeviceLoopRendererTest,
    ::testing::Values(TinyLoopModelCase{"Degree3", 3, true, true},
                      TinyLoopModelCase{"Degree0", 0, true, true},
                      TinyLoopModelCase{"NoMotionField", 1, false, true},
                      TinyLoopModelCase{"NoResidualField", 1, true, false}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace cuda
}  // namespace es
