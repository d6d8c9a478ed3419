// One command from an MP4 with no poses and no masks to the looping video:
// a tiny es_synth scene is encoded as MP4, and the driver decodes it, gets
// poses, finds the water masks itself, trains and animates. COLMAP is not
// reliable on frames this small, so the pose step is swapped (--pose_script)
// for one that copies the synthetic scene's exact poses; es_poses itself is
// measured in docs/results/video.md (today's figures in docs/RESULTS.md).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "core/masks/water_masks.h"
#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

std::string FrameName(int f) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06d.png", f);
  return name;
}

constexpr int kFrames = 16, kWidth = 96, kHeight = 72;

TEST(VideoEndToEndTest, FromAnMp4ToTheLoopingVideo) {
  ASSERT_TRUE(AppsBuilt({"es_synth", "eulersplat", "es_masks", "es_static",
                         "es_train", "es_animate", "es_eval"}));
  const fs::path root = FreshBuildDir("video_end_to_end_test");
  const fs::path synth = root / "synth", out = root / "out";
  std::string log;
  ASSERT_EQ(RunCommand((kBin / "es_synth").string() + " --out " +
                           synth.string() + " --frames " +
                           std::to_string(kFrames) + " --width " +
                           std::to_string(kWidth) + " --height " +
                           std::to_string(kHeight) +
                           " --detail 0.08 --num_points 400 --seed 3",
                       &log),
            0)
      << log;

  // The frames as an MP4, the user's only input.
  const fs::path video = root / "waterfall.mp4";
  {
    cv::VideoWriter writer(video.string(),
                           cv::VideoWriter::fourcc('m', 'p', '4', 'v'), 30,
                           cv::Size(kWidth, kHeight));
    ASSERT_TRUE(writer.isOpened()) << "OpenCV cannot write MP4";
    for (int f = 0; f < kFrames; ++f) {
      const cv::Mat frame =
          cv::imread((synth / "images" / FrameName(f)).string());
      ASSERT_FALSE(frame.empty());
      writer.write(frame);
    }
  }
  const fs::path poses = root / "exact_poses.sh";
  std::ofstream(poses) << "mkdir -p \"$1/sparse/0\" && cp "
                       << (synth / "sparse" / "0").string()
                       << "/*.txt \"$1/sparse/0/\"\n";

  const std::string driver =
      (kBin / "eulersplat").string() + " --video " + video.string() +
      " --out " + out.string() + " --pose_script " + poses.string() +
      " --preset quick --static_iterations 150 --mask_probe_iterations 150"
      " --flow_iterations 20 --joint_iterations 20 --cycle_length 4"
      " --animate_frames 8";
  log.clear();
  ASSERT_EQ(RunCommand(driver, &log), 0) << log;
  for (const char* step : {"[video] frame 16 / 16", "[poses]", "[masks]"})
    EXPECT_THAT(log, HasSubstr(step)) << step << "\n" << log;

  // Every frame decoded, and a mask a person can edit for each.
  double iou = 0;
  for (int f = 0; f < kFrames; ++f) {
    const fs::path image = out / "scene" / "images" / FrameName(f);
    ASSERT_TRUE(fs::exists(image)) << image;
    const cv::Mat mask = cv::imread(
        (out / "scene" / "masks" / FrameName(f)).string(),
        cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(mask.size(), cv::Size(kWidth, kHeight)) << f << "\n" << log;
    const cv::Mat truth = cv::imread(
        (synth / "masks" / FrameName(f)).string(), cv::IMREAD_GRAYSCALE);
    iou += es::MaskIou(mask, truth) / kFrames;
  }
  EXPECT_GT(iou, 0.4) << log;
  for (const char* file :
       {"masks_sheet.png", "masks_report.json", "static/static.ply",
        "model/loop.txt", "animate/animation.mp4", "eval/eval.json",
        "contact_sheet.png"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file << "\n" << log;
  }
  const std::string json = ReadWholeFile(out / "eval" / "eval.json");
  EXPECT_GT(JsonNumber(json, "psnr"), 10.0) << json;
  EXPECT_GT(JsonNumber(json, "dynamic_gaussians"), 0) << json;

  // Nothing is redone on a second run.
  log.clear();
  ASSERT_EQ(RunCommand(driver, &log), 0) << log;
  for (const char* stage :
       {"[video] skipped", "[masks] using", "[static] skipped"})
    EXPECT_THAT(log, HasSubstr(stage)) << stage << "\n" << log;

  // --masks none: a static model, a clear message, no motion training.
  const fs::path still = root / "still";
  log.clear();
  ASSERT_EQ(RunCommand((kBin / "eulersplat").string() + " --scene " +
                           (out / "scene").string() + " --out " +
                           still.string() +
                           " --masks none --static_iterations 20",
                       &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("training the static model only"));
  EXPECT_TRUE(fs::exists(still / "static" / "static.ply"));
  EXPECT_FALSE(fs::exists(still / "model"));
  EXPECT_FALSE(fs::exists(still / "scene" / "masks"));
}

TEST(VideoEndToEndTest, BadVideoIsAClearError) {
  const fs::path root = FreshBuildDir("video_end_to_end_bad");
  fs::create_directories(root);
  std::ofstream(root / "broken.mp4") << "not a video";
  std::string log;
  EXPECT_EQ(RunCommand((kBin / "eulersplat").string() + " --video " +
                           (root / "broken.mp4").string() + " --out " +
                           (root / "out").string(),
                       &log),
            1);
  EXPECT_THAT(log, HasSubstr("broken.mp4"));
  log.clear();
  EXPECT_EQ(RunCommand((kBin / "eulersplat").string() + " --out " +
                           (root / "out").string(),
                       &log),
            1);
  EXPECT_THAT(log, HasSubstr("--video"));
}

}  // namespace
}  // namespace es
