// es_animate's frames on the device (cuda::DeviceLoopFrames, what
// --device cuda plays) against the CPU's (CpuLoopFrames, --device cpu):
// a tiny looping model with V and D, a non-black background, frame by
// frame over more than a cycle from a late start. Two float rasterizers
// apart: at most 0.5% of the RGB values off by more than 2e-5 of the
// largest, none by more than 0.05. Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/loop/cuda/device_loop_frames.h"
#include "core/loop/loop_frames.h"
#include "tests/cuda/require_gpu.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 3;

// 16 Gaussians in front of the camera, half of them water, with small
// fields whose motion and offsets show in the image.
LoopModel TinyModel() {
  LoopModel m;
  m.cycle_length = kCycle;
  GaussianSet& g = m.gaussians;
  g.sh_degree = 1;
  g.Resize(16);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : g.means) v = 0.6 * u(rng);
  for (int n = 0; n < g.size(); ++n) g.means[3 * n + 2] += 4.0;
  for (double& v : g.log_scales) v = -1.8 + 0.2 * u(rng);
  for (double& v : g.opacity_logits) v = 1 + u(rng);
  for (double& v : g.sh) v = 0.8 * u(rng);
  m.dynamic_index = {0, 3, 4, 7, 9, 10, 12, 15};
  m.start_times = {0, 2, 1, 0, 2, 1, 0, 1};
  const Eigen::Vector3d lo(-1, -1, 3), hi(1, 1, 5);
  MotionFieldOptions v;
  v.triplane.resolution = 8;
  v.triplane.channels = 4;
  v.mlp_width = 16;
  v.velocity_scale = 0.1;
  v.last_layer_init_scale = 1.0;
  v.seed = 5;
  m.motion.emplace(v);
  m.motion->SetBox(lo, hi);
  ResidualFieldOptions d;
  d.triplane.resolution = 8;
  d.triplane.channels = 4;
  d.cycle_length = kCycle;
  d.mlp_width = 16;
  d.mlp_depth = 1;
  d.last_layer_init_scale = 1.0;
  d.seed = 7;
  m.residual.emplace(d);
  m.residual->SetBox(lo, hi);
  return m;
}

Camera TestCamera() {
  Camera c;
  c.width = 32;
  c.height = 24;
  c.fx = c.fy = 36;
  c.cx = 16;
  c.cy = 12;
  return c;
}

// How many values differ by more than tol times the largest |want|, and
// the largest difference so scaled.
void ExpectFramesClose(const std::vector<double>& got,
                       const std::vector<double>& want) {
  ASSERT_EQ(got.size(), want.size());
  double scale = 0;
  for (double v : want) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0);
  size_t off = 0;
  double largest = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    const double d = std::abs(got[i] - want[i]) / scale;
    if (!(d <= 2e-5)) ++off;  // NaN counts
    if (!(d <= largest)) largest = d;
  }
  EXPECT_LE(off, 0.005 * want.size())
      << off << " of " << want.size() << " values off (largest " << largest
      << ")";
  EXPECT_LE(largest, 0.05);
}

TEST(CudaLoopFramesTest, DeviceFramesAreTheCpuFrames) {
  ES_REQUIRE_GPU("device path of es_animate");
  const LoopModel model = TinyModel();
  RenderOptions options;
  options.background = Eigen::Vector3d(0.2, 0.5, 0.9);
  CpuLoopFrames cpu(&model, options);
  DeviceLoopFrames device(&model, options);
  EXPECT_EQ(device.cpu_renderer(), nullptr);
  const Camera camera = TestCamera();
  const int first = 2;
  cpu.Start(first);
  device.Start(first);
  std::vector<double> previous;
  double change = 0;  // not vacuous: the water moves between frames
  for (int frame = first; frame <= first + kCycle + 1; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    if (frame > first) {
      cpu.Advance();
      device.Advance();
    }
    const std::vector<double> want = cpu.Rgb(camera);
    const std::vector<double>& got = device.Rgb(camera);
    ASSERT_EQ(got.size(), 3u * camera.width * camera.height);
    ExpectFramesClose(got, want);
    for (size_t i = 0; i < previous.size(); ++i)
      change = std::max(change, std::abs(want[i] - previous[i]));
    previous = want;
  }
  EXPECT_GT(change, 0.02);
}

}  // namespace
}  // namespace cuda
}  // namespace es
