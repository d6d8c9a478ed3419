// es_eval's rendering on the device (--device cuda: cuda::DeviceLoopFrames
// plays the loop, cuda::DeviceImageRasterizer renders Alg. 1's
// compositions) against the CPU's (--device cpu), on a tiny looping model
// seen by five input frames whose time indices skip one (an unregistered
// frame): the held-out compositions and the realism video of the model and
// of its breakdown variants (no D; no V and no D) frame by frame, two float
// rasterizers apart (expect_frames_close.h), and the figures made from
// them: held-out PSNR / SSIM and the loop-seam score. Skips when no CUDA
// device is present.

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/loop/cuda/device_loop_frames.h"
#include "core/loop/loop_frames.h"
#include "core/render/cuda/device_image_rasterizer.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/realism_evaluation.h"
#include "tests/cuda/expect_frames_close.h"
#include "tests/cuda/require_gpu.h"
#include "tests/cuda/tiny_loop_model.h"

namespace es {
namespace cuda {
namespace {

constexpr int kCycle = 3;

RenderOptions Options() {
  RenderOptions o;
  o.background = Eigen::Vector3d(0.2, 0.5, 0.9);
  return o;
}

Camera TestCamera(int time) {
  Camera c;
  c.width = 40;
  c.height = 30;
  c.fx = c.fy = 44;
  c.cx = 19 + 0.5 * time;  // the input camera moves a little
  c.cy = 15;
  return c;
}

// Input frames at time indices 0 1 2 4 5 (3 unregistered); each image is
// the CPU's render of the model's composition one frame later, so that
// the figures are finite, and the mask marks the left half as water.
std::vector<Frame> InputFrames(const LoopModel& model) {
  std::vector<Frame> frames;
  for (int time : {0, 1, 2, 4, 5}) {
    Frame f;
    f.camera = TestCamera(time);
    f.time_index = time;
    f.mask = cv::Mat::zeros(f.camera.height, f.camera.width, CV_32FC1);
    f.mask.colRange(0, f.camera.width / 2).setTo(1.0);
    frames.push_back(f);
  }
  std::vector<Frame> later = frames;
  for (Frame& f : later) ++f.time_index;
  CpuImageRasterizer cpu(Options());
  const std::vector<cv::Mat> images =
      RenderCompositions(model, later, {0, 1, 2, 3, 4}, &cpu);
  for (size_t i = 0; i < frames.size(); ++i)
    images[i].convertTo(frames[i].image, CV_32FC3);
  return frames;
}

std::vector<double> Values(const cv::Mat& image) {
  const cv::Mat flat = image.reshape(1, 1);
  return std::vector<double>(flat.begin<double>(), flat.end<double>());
}

void ExpectVideosClose(const std::vector<cv::Mat>& got,
                       const std::vector<cv::Mat>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    ASSERT_EQ(got[i].size(), want[i].size());
    ASSERT_EQ(got[i].type(), CV_64FC3);
    ExpectFramesClose(Values(got[i]), Values(want[i]));
  }
}

TEST(CudaEvalRenderingTest, HeldOutFramesAndFiguresAreTheCpus) {
  ES_REQUIRE_GPU("device rendering of es_eval's held-out frames");
  const LoopModel model =
      TinyLoopModel({"V and D", 1, true, true}, kCycle, 0.1);
  const std::vector<Frame> frames = InputFrames(model);
  const std::vector<int> held_out = {1, 3, 4};
  CpuImageRasterizer cpu(Options());
  DeviceImageRasterizer device(Options());
  ExpectVideosClose(RenderCompositions(model, frames, held_out, &device),
                    RenderCompositions(model, frames, held_out, &cpu));
  const LoopMetrics want = EvaluateLoopModel(model, frames, held_out, &cpu);
  const LoopMetrics got = EvaluateLoopModel(model, frames, held_out, &device);
  // Not vacuous: the renders differ from the inputs (finite PSNR).
  ASSERT_TRUE(std::isfinite(want.psnr) && std::isfinite(want.psnr_water));
  EXPECT_LT(want.psnr, 60);
  EXPECT_EQ(got.frames, 3);
  EXPECT_NEAR(got.psnr, want.psnr, 0.01);
  EXPECT_NEAR(got.psnr_water, want.psnr_water, 0.01);
  EXPECT_NEAR(got.ssim, want.ssim, 1e-3);
  EXPECT_NEAR(got.ssim_water, want.ssim_water, 1e-3);
}

TEST(CudaEvalRenderingTest, RealismVideosAreTheCpus) {
  ES_REQUIRE_GPU("device rendering of es_eval's realism video");
  for (const TinyLoopModelCase& c :
       {TinyLoopModelCase{"V and D", 1, true, true},
        TinyLoopModelCase{"loop_without_residual", 1, true, false},
        TinyLoopModelCase{"canonical", 1, false, false}}) {
    SCOPED_TRACE(c.name);
    const LoopModel model = TinyLoopModel(c, kCycle, 0.1);
    const std::vector<Frame> frames = InputFrames(model);
    CpuLoopFrames cpu(&model, Options());
    DeviceLoopFrames device(&model, Options());
    ExpectVideosClose(RenderAtInputCameras(&device, frames),
                      RenderAtInputCameras(&cpu, frames));
  }
}

TEST(CudaEvalRenderingTest, LoopSeamScoreIsTheCpus) {
  ES_REQUIRE_GPU("device rendering of es_eval's loop seam");
  const LoopModel model =
      TinyLoopModel({"V and D", 1, true, true}, kCycle, 0.1);
  const Camera camera = TestCamera(0);
  CpuLoopFrames cpu(&model, Options());
  DeviceLoopFrames device(&model, Options());
  const LoopSeamScore want = EvaluateLoopSeam(&cpu, kCycle, camera, 2);
  const LoopSeamScore got = EvaluateLoopSeam(&device, kCycle, camera, 2);
  ASSERT_GT(want.within_change, 0);  // the water moves: not vacuous
  EXPECT_EQ(got.boundary_pairs, want.boundary_pairs);
  EXPECT_EQ(got.within_pairs, want.within_pairs);
  EXPECT_NEAR(got.within_change, want.within_change,
              1e-3 * want.within_change);
  EXPECT_NEAR(got.boundary_change, want.boundary_change,
              1e-3 * want.within_change);
  EXPECT_NEAR(got.score, want.score, 1e-3 * std::abs(want.score) + 1e-3);
}

}  // namespace
}  // namespace cuda
}  // namespace es
