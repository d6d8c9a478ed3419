// Video import: which frames are kept (rate, count, width), their order,
// masks resized with them, and clear errors.

#include "core/io/video_import.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "core/io/frame_loading.h"
#include "core/base/input_error.h"
#include "tests/expect_error.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 64, kHeight = 48, kFrames = 12;

// Frame f is a flat color whose blue channel encodes f (MJPG keeps flat
// colors to within a few levels).
cv::Scalar FrameColor(int f) { return cv::Scalar(20 * f, 120, 60); }

class VideoImportTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    video_ = Path("clip.avi");
    cv::VideoWriter writer(video_, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                           30, cv::Size(kWidth, kHeight));
    ASSERT_TRUE(writer.isOpened());
    for (int f = 0; f < kFrames; ++f)
      writer.write(cv::Mat(kHeight, kWidth, CV_8UC3, FrameColor(f)));
  }

  // Which video frame an imported frame shows.
  int SourceFrame(const std::string& scene, int k) {
    const cv::Mat image =
        cv::imread((fs::path(scene) / "images" / VideoFrameName(k)).string());
    EXPECT_FALSE(image.empty()) << k;
    return static_cast<int>(std::lround(cv::mean(image)[0] / 20));
  }

  std::string video_;
};

TEST_F(VideoImportTest, KeepsEveryFrameByDefault) {
  const std::string scene = Path("scene");
  VideoImportOptions options;
  int calls = 0;
  const VideoImportResult r =
      ImportVideo(video_, scene, options, [&](int, int) { ++calls; });
  EXPECT_EQ(r.frames, kFrames);
  EXPECT_EQ(r.step, 1);
  EXPECT_EQ(calls, kFrames);
  EXPECT_NEAR(r.video_fps, 30, 0.01);
  for (int k = 0; k < kFrames; ++k) EXPECT_EQ(SourceFrame(scene, k), k);
  EXPECT_FALSE(fs::exists(fs::path(scene) / "images" /
                          VideoFrameName(kFrames)));
}

TEST_F(VideoImportTest, RateCountAndWidth) {
  const std::string scene = Path("scene");
  VideoImportOptions options;
  options.fps = 10;  // every 3rd of 30 fps
  options.max_frames = 3;
  options.max_width = 32;
  const VideoImportResult r = ImportVideo(video_, scene, options);
  EXPECT_EQ(r.step, 3);
  EXPECT_EQ(r.frames, 3);
  EXPECT_EQ(r.width, 32);
  EXPECT_EQ(r.height, 24);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(SourceFrame(scene, k), 3 * k);
  const cv::Mat first = cv::imread(
      (fs::path(scene) / "images" / VideoFrameName(0)).string());
  EXPECT_EQ(first.size(), cv::Size(32, 24));
  EXPECT_FALSE(fs::exists(fs::path(scene) / "images" / VideoFrameName(3)));
}

TEST_F(VideoImportTest, MasksFollowTheirFrames) {
  const fs::path masks = dir_ / "user_masks";
  fs::create_directories(masks);
  for (int f = 0; f < kFrames; ++f) {
    // Water in the left f columns of 12: tells which frame it belongs to.
    cv::Mat m(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    m(cv::Rect(0, 0, f * kWidth / kFrames, kHeight)).setTo(255);
    ASSERT_TRUE(cv::imwrite((masks / VideoFrameName(f)).string(), m));
  }
  const std::string scene = Path("scene");
  VideoImportOptions options;
  options.fps = 15;  // every 2nd
  options.max_width = 32;
  options.masks_dir = masks.string();
  const VideoImportResult r = ImportVideo(video_, scene, options);
  ASSERT_EQ(r.frames, kFrames / 2);
  for (int k = 0; k < r.frames; ++k) {
    const cv::Mat m = cv::imread(
        (fs::path(scene) / "masks" / VideoFrameName(k)).string(),
        cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(m.size(), cv::Size(32, 24));
    EXPECT_NEAR(cv::countNonZero(m) / 24.0, 2 * k * 32.0 / kFrames, 1.01)
        << "frame " << k;
  }
}

TEST_F(VideoImportTest, ErrorsNameTheProblem) {
  auto expect_error = [](const std::function<void()>& f,
                         const std::string& part) {
    ExpectErrorNaming<InputError>(f, {part});
  };
  expect_error([&] { ImportVideo(Path("none.mp4"), Path("s"), {}); },
               "none.mp4");
  VideoImportOptions bad;
  bad.max_frames = 1;
  expect_error([&] { ImportVideo(video_, Path("s"), bad); }, "--max_frames");
  ImportVideo(video_, Path("twice"), {});
  expect_error([&] { ImportVideo(video_, Path("twice"), {}); },
               "already holds files");
  const std::string text = Path("not_a_video.mp4");
  std::ofstream(text) << "hello";
  expect_error([&] { ImportVideo(text, Path("t"), {}); }, "not_a_video.mp4");
}

}  // namespace
}  // namespace es
