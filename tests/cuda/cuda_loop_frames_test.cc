// es_animate's frames on the device (cuda::DeviceLoopFrames, what
// --device cuda plays) against the CPU's (CpuLoopFrames, --device cpu):
// a tiny looping model with V and D, a non-black background, frame by
// frame over more than a cycle from a late start, two float rasterizers
// apart (expect_frames_close.h). Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/loop/cuda/device_loop_frames.h"
#include "core/loop/loop_frames.h"
#include "tests/centered_camera.h"
#include "tests/cuda/expect_frames_close.h"
#include "tests/cuda/require_gpu.h"
#include "tests/cuda/tiny_loop_model.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 3;

Camera TestCamera() { return CenteredCamera(32, 24, 36); }

TEST(CudaLoopFramesTest, DeviceFramesAreTheCpuFrames) {
  ES_REQUIRE_GPU("device path of es_animate");
  const LoopModel model =
      TinyLoopModel({"V and D", 1, true, true}, kCycle, 0.1);
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
