// The device loop renderer against its CPU twin, LoopRenderer: the
// composed splats of every frame over more than a cycle (V's Euler step
// per frame, D at p = 0 on positions, opacity and up to 16 SH
// coefficients), for SH degrees below and at D's 16 coefficients and
// models without V or without D; and the rendered frame against the
// device rasterizer's render of the CPU-composed splats. Double on both
// sides: splats within 1e-9 relative. Skips when no CUDA device is
// present.

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/loop/cuda/device_loop_renderer.h"
#include "core/loop/loop_renderer.h"
#include "core/model/gaussians.h"
#include "core/render/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "tests/cuda/expect_twins_near.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 4;
constexpr double kTolerance = 1e-9;

struct ModelCase {
  const char* name;
  int sh_degree;
  bool motion, residual;
};

// frame_composer_test.cc's tiny model, larger: 24 Gaussians in front of
// the camera, 10 of them dynamic, small fields far from zero.
LoopModel TinyModel(const ModelCase& c) {
  LoopModel m;
  m.cycle_length = kCycle;
  GaussianSet& g = m.gaussians;
  g.sh_degree = c.sh_degree;
  g.Resize(24);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : g.means) v = 0.8 * u(rng);
  for (int n = 0; n < g.size(); ++n) g.means[3 * n + 2] += 4.0;
  for (double& v : g.log_scales) v = -2 + 0.2 * u(rng);
  for (double& v : g.opacity_logits) v = u(rng);
  for (double& v : g.sh) v = 0.5 * u(rng);
  m.dynamic_index = {1, 2, 4, 6, 9, 11, 15, 18, 20, 23};
  m.start_times = {0, 3, 1, 2, 2, 0, 3, 1, 0, 2};
  const Eigen::Vector3d lo(-1, -1, 3), hi(1, 1, 5);
  if (c.motion) {
    MotionFieldOptions o;
    o.triplane.resolution = 8;
    o.triplane.channels = 4;
    o.mlp_width = 16;
    o.velocity_scale = 0.05;
    o.last_layer_init_scale = 1.0;
    o.seed = 5;
    m.motion.emplace(o);
    m.motion->SetBox(lo, hi);
  }
  if (c.residual) {
    ResidualFieldOptions o;
    o.triplane.resolution = 8;
    o.triplane.channels = 4;
    o.cycle_length = kCycle;
    o.mlp_width = 16;
    o.mlp_depth = 1;
    o.last_layer_init_scale = 1.0;
    o.seed = 7;
    m.residual.emplace(o);
    m.residual->SetBox(lo, hi);
  }
  return m;
}

std::vector<double> Fetch(const double* device, size_t count) {
  std::vector<double> host(count);
  CopyToHost(host.data(), device, count * sizeof(double));
  return host;
}

std::vector<double> Copy(const double* host, size_t count) {
  return std::vector<double>(host, host + count);
}

class DeviceLoopRendererTest : public ::testing::TestWithParam<ModelCase> {};

TEST_P(DeviceLoopRendererTest, ComposesAndRendersAsCpuTwin) {
  ES_REQUIRE_GPU("CUDA loop renderer");
  const LoopModel model = TinyModel(GetParam());
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
  Camera camera;
  camera.width = 40;
  camera.height = 30;
  camera.fx = camera.fy = 40;
  camera.cx = 20;
  camera.cy = 15;
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
    ::testing::Values(ModelCase{"Degree3", 3, true, true},
                      ModelCase{"Degree0", 0, true, true},
                      ModelCase{"NoMotionField", 1, false, true},
                      ModelCase{"NoResidualField", 1, true, false}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace cuda
}  // namespace es
