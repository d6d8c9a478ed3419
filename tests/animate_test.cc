// Render-level checks of the animation path es_animate and es_eval use:
// Alg. 2 loops exactly with period L, agrees with Alg. 1, and the outputs
// built on it (tracks, x-t slices, videos) are what they claim.

#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "core/base/input_error.h"
#include "core/loop/cycle_time.h"
#include "core/loop/loop_renderer.h"
#include "core/loop/loop_model.h"
#include "core/viz/camera_path.h"
#include "core/viz/tracks.h"
#include "core/viz/video_writer.h"
#include "core/viz/xt_slice.h"
#include "solvers/eval/loop_evaluation.h"
#include "tests/centered_camera.h"
#include "tests/water_loop_fixture.h"

namespace es {
namespace {

constexpr int kL = 5;

Camera TestCamera() {
  return LookAt(CenteredCamera(40, 32, 40), {0, 0, -3}, {0, 0, 0}, {0, -1, 0});
}

// A few static and dynamic Gaussians around the origin, a motion field
// fast enough that a cycle moves them by several pixels, and a residual
// field whose outputs are not negligible.
LoopModel TinyModel(bool with_residual) {
  LoopModel m;
  m.cycle_length = kL;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  const int n = 240;
  m.gaussians.Resize(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 3; ++j) {
      m.gaussians.means[3 * i + j] = u(rng);
      m.gaussians.log_scales[3 * i + j] = std::log(0.15);
      m.gaussians.sh[3 * i + j] = 2.0 * u(rng);
    }
    m.gaussians.opacity_logits[i] = 1.0;
    if (i % 3 != 0) {  // two thirds water
      m.dynamic_index.push_back(i);
      m.gaussians.dynamic_logits[i] = 3.0;
    }
  }
  m.start_times = RandomStartTimes(m.num_dynamic(), kL, 3);
  m.motion.emplace(SmallMotionFieldOptions(0.01));
  m.motion->SetBox({-1, -1, -1}, {1, 1, 1});
  m.motion->Initialize(5);
  if (with_residual) {
    m.residual.emplace(SmallResidualFieldOptions(kL));
    m.residual->SetBox({-1, -1, -1}, {1, 1, 1});
    m.residual->Initialize(6);
  }
  return m;
}

TEST(AnimateTest, FixedViewFramesRepeatWithPeriodL) {
  for (bool with_residual : {false, true}) {
    const LoopModel model = TinyModel(with_residual);
    LoopRenderer renderer(&model, RenderOptions());
    const Camera camera = TestCamera();
    std::vector<std::vector<double>> frames;
    renderer.Start(0);
    for (int k = 0; k < 3 * kL; ++k) {
      if (k > 0) renderer.Advance();
      frames.push_back(renderer.Render(camera).rgb);
    }
    for (int k = 0; k + kL < static_cast<int>(frames.size()); ++k) {
      EXPECT_EQ(frames[k], frames[k + kL]) << "frame " << k;
    }
    // Not vacuous: the water moves within a cycle.
    double change = 0;
    for (size_t i = 0; i < frames[0].size(); ++i) {
      change = std::max(change, std::abs(frames[1][i] - frames[0][i]));
    }
    EXPECT_GT(change, 0.05);
  }
}

TEST(AnimateTest, StartingLateMatchesPlayingThrough) {
  const LoopModel model = TinyModel(true);
  const Camera camera = TestCamera();
  LoopRenderer through(&model, RenderOptions());
  through.Start(0);
  for (int k = 0; k < kL + 2; ++k) through.Advance();
  LoopRenderer late(&model, RenderOptions());
  late.Start(2);  // same frame modulo L
  const std::vector<double> a = through.Render(camera).rgb;
  const std::vector<double>& b = late.Render(camera).rgb;
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9);
}

TEST(AnimateTest, Alg2AgreesWithAlg1) {
  const LoopModel model = TinyModel(true);
  const AnimationTiming t =
      TimeAnimation(model, TestCamera(), 2 * kL, RenderOptions());
  EXPECT_EQ(t.num_dynamic, model.num_dynamic());
  EXPECT_LT(t.max_position_difference, 1e-9);
  EXPECT_GT(t.render_ms, 0.0);
}

TEST(AnimateTest, StaggeredStartsGiveSeamlessLoopAndSyncedStartsDoNot) {
  LoopModel model = TinyModel(false);
  const Camera camera = TestCamera();
  const double staggered =
      EvaluateLoopSeam(model, camera, 3, RenderOptions()).score;
  std::fill(model.start_times.begin(), model.start_times.end(), 0);
  const double synced =
      EvaluateLoopSeam(model, camera, 3, RenderOptions()).score;
  EXPECT_NEAR(staggered, 1.0, 0.25);
  EXPECT_GT(synced, 2.0);
}

TEST(AnimateTest, TracksDrawOnlyInFrontAndBreakAtResets) {
  const Camera camera = TestCamera();
  TrackHistory tracks(2, 4);
  // Track 0 moves right across the image center; track 1 is behind the
  // camera and must draw nothing.
  const double p0[6] = {-0.5, 0, 0, 0, 0, -4};
  const double p1[6] = {0.5, 0, 0, 0.1, 0, -4};
  tracks.Push(p0, {});
  tracks.Push(p1, {});
  cv::Mat image(camera.height, camera.width, CV_8UC3, cv::Scalar::all(0));
  tracks.Draw(camera, &image);
  EXPECT_GT(cv::countNonZero(image.reshape(1)), camera.width / 4);
  EXPECT_GT(cv::norm(image.at<cv::Vec3b>(16, 20)), 0.0);  // passes center
  EXPECT_EQ(cv::norm(image.row(2)), 0.0);  // nothing far from the line

  // A reset between the two positions: no segment at all.
  TrackHistory reset(2, 4);
  reset.Push(p0, {});
  reset.Push(p1, {true, true});
  cv::Mat empty(camera.height, camera.width, CV_8UC3, cv::Scalar::all(0));
  reset.Draw(camera, &empty);
  EXPECT_EQ(cv::countNonZero(empty.reshape(1)), 0);
}

TEST(AnimateTest, TrackSubsetIsSortedDistinctAndBounded) {
  const std::vector<int> s = SelectTrackSubset(100, 10, 4);
  ASSERT_EQ(s.size(), 10u);
  for (size_t i = 1; i < s.size(); ++i) EXPECT_LT(s[i - 1], s[i]);
  EXPECT_GE(s.front(), 0);
  EXPECT_LT(s.back(), 100);
  EXPECT_EQ(SelectTrackSubset(5, 10, 4).size(), 5u);
}

TEST(AnimateTest, XtSliceStacksTheRowOverTime) {
  XtSlice slice(3);
  for (int k = 0; k < 4; ++k) {
    cv::Mat f(6, 5, CV_8UC3, cv::Scalar::all(0));
    f.row(3).setTo(cv::Scalar::all(10 * (k + 1)));
    slice.Add(f);
  }
  ASSERT_EQ(slice.frames(), 4);
  EXPECT_EQ(slice.image().cols, 5);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(slice.image().at<cv::Vec3b>(k, 2)[1], 10 * (k + 1));
  }
  XtSlice outside(6);
  EXPECT_THROW(outside.Add(cv::Mat(6, 5, CV_8UC3)), InputError);
}

TEST(AnimateTest, VideoWriterWritesFramesAndAPlayableMp4) {
  const std::string dir = std::string(ES_BINARY_DIR) + "/animate_test_video";
  std::filesystem::remove_all(dir);
  VideoWriter writer(dir + "/frames", 10);
  for (int k = 0; k < 6; ++k) {
    // Odd size on purpose: H.264 needs padding to even.
    writer.Add(cv::Mat(31, 41, CV_8UC3, cv::Scalar(40 * k, 100, 200)));
  }
  const std::string encoder = writer.Finish(dir + "/video.mp4");
  EXPECT_TRUE(encoder == "ffmpeg" || encoder == "opencv-mp4v");
  EXPECT_TRUE(std::filesystem::exists(dir + "/frames/frame_000005.png"));
  cv::VideoCapture capture(dir + "/video.mp4");
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  cv::Mat f;
  while (capture.read(f)) ++frames;
  EXPECT_EQ(frames, 6);
  // A second, shorter run leaves no stale frames behind.
  VideoWriter again(dir + "/frames", 10);
  EXPECT_FALSE(std::filesystem::exists(dir + "/frames/frame_000000.png"));
}

TEST(AnimateTest, RgbToBgr8ClampsAndSwapsChannels) {
  const double rgb[6] = {1.0, 0.5, 0.0, -0.2, 2.0, std::nan("")};
  const cv::Mat bgr = RgbToBgr8(rgb, 2, 1);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 128, 255));
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 255, 0));
}

}  // namespace
}  // namespace es
