// The whole pipeline on a tiny synthetic scene: es_synth, then the
// eulersplat driver with a few iterations of every stage. Checks that every
// stage ran and left its outputs, that the metrics are finite, that the
// fixed-view video loops, and that a second run skips every stage.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

TEST(EndToEndTest, DriverRunsEveryStageAndResumes) {
  ASSERT_TRUE(AppsBuilt({"es_synth", "eulersplat", "es_static", "es_flowinit",
                         "es_train", "es_animate", "es_export", "es_eval"}));
  const fs::path root = FreshBuildDir("end_to_end_test");
  const fs::path scene = root / "scene", out = root / "out";
  std::string log;
  ASSERT_EQ(RunCommand((kBin / "es_synth").string() + " --out " +
                           scene.string() +
                           " --frames 20 --width 64 --height 48"
                           " --detail 0.05 --num_points 400",
                       &log),
            0)
      << log;

  constexpr int kL = 5;
  const std::string driver =
      (kBin / "eulersplat").string() + " --scene " + scene.string() +
      " --out " + out.string() +
      " --preset quick --static_iterations 40 --flow_iterations 20"
      " --joint_iterations 20 --cycle_length " + std::to_string(kL) +
      " --animate_frames " + std::to_string(3 * kL);
  log.clear();
  ASSERT_EQ(RunCommand(driver, &log), 0) << log;

  // --device (default cpu) reaches every stage run that takes it:
  // es_static, es_flowinit, es_train, both es_animate videos and es_eval.
  int device_stages = 0;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("$ ", 0) != 0) continue;
    for (const char* stage :
         {"/es_static ", "/es_flowinit ", "/es_train ", "/es_animate ",
          "/es_eval "}) {
      if (line.find(stage) == std::string::npos) continue;
      ++device_stages;
      EXPECT_THAT(line, HasSubstr(" --device cpu"));
    }
  }
  EXPECT_EQ(device_stages, 6) << log;

  for (const char* file :
       {"static/static.ply", "static/motion_field.bin", "model/loop.txt",
        "model/canonical.ply", "animate/animation.mp4", "animate/tracks.mp4",
        "animate/frames/frame_000014.png", "animate_fixed/animation.mp4",
        "animate_fixed/xt_slice.png", "eval/eval.json",
        "contact_sheet.png", "frame_0.ply"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file << "\n" << log;
  }
  // The web page needs the npm packages scripts/setup.sh installs.
  const bool have_viewer =
      fs::exists(fs::path(ES_SOURCE_DIR) /
                 "web/node_modules/@sparkjsdev/spark/dist/spark.module.js");
  if (have_viewer) {
    for (const char* file : {"web/index.html", "web/scene.esloop",
                             "web/view.json", "web/lib/spark/spark.module.js"})
      EXPECT_TRUE(fs::exists(out / file)) << file << "\n" << log;
  }
  EXPECT_FALSE(fs::exists(out / "animate/frames/frame_000015.png"));

  const std::string json = ReadWholeFile(out / "eval" / "eval.json");
  for (const char* key :
       {"psnr", "ssim", "psnr_water", "ssim_water", "epe", "score",
        "alg1_frame", "alg2_frame"}) {
    EXPECT_TRUE(std::isfinite(JsonNumber(json, key))) << key << "\n" << json;
  }
  EXPECT_GT(JsonNumber(json, "psnr"), 5.0) << json;
  EXPECT_GT(JsonNumber(json, "dynamic_gaussians"), 0) << json;
  EXPECT_THAT(json, HasSubstr("\"device\": \"cpu\""));

  // The driver has es_eval measure Stage 2's V at the model's own water
  // Gaussians; with the model's own V as the reference, the two figures
  // are the same (the same points, the same field).
  const nlohmann::json eval = nlohmann::json::parse(json);
  ASSERT_TRUE(eval["motion_gt"].contains("reference")) << json;
  EXPECT_EQ(eval["motion_gt"]["reference"]["field"],
            (out / "static" / "motion_field.bin").string());
  EXPECT_TRUE(std::isfinite(
      eval["motion_gt"]["reference"]["rel_epe"].get<double>()));
  const auto eval_with_reference = [&](const fs::path& eval_out,
                                       const fs::path& reference) {
    log.clear();
    return RunCommand((kBin / "es_eval").string() + " --scene " +
                          scene.string() + " --model " +
                          (out / "model").string() + " --out " +
                          eval_out.string() +
                          " --compare_frames 0 --reference_motion " +
                          reference.string(),
                      &log);
  };
  ASSERT_EQ(eval_with_reference(root / "self_eval",
                                out / "model" / "motion_field.bin"),
            0)
      << log;
  const nlohmann::json self =
      nlohmann::json::parse(ReadWholeFile(root / "self_eval" / "eval.json"));
  EXPECT_EQ(self["motion_gt"]["reference"]["epe"].get<double>(),
            self["motion_gt"]["epe"].get<double>());
  EXPECT_EQ(self["motion_gt"]["epe"].get<double>(),
            eval["motion_gt"]["epe"].get<double>());
  // The held-out images are what the held-out PSNR scores: one per
  // held-out frame, render left and input right, whose PSNR (8-bit, so
  // to within a few hundredths of a dB) averages to eval.json's.
  const fs::path held_out = root / "self_eval" / "held_out";
  double psnr_sum = 0;
  int images = 0;
  for (const auto& entry : fs::directory_iterator(held_out)) {
    const cv::Mat side = cv::imread(entry.path().string());
    ASSERT_FALSE(side.empty()) << entry.path();
    const int w = side.cols / 2;
    psnr_sum += cv::PSNR(side.colRange(0, w), side.colRange(w, 2 * w));
    ++images;
  }
  EXPECT_EQ(images, self["held_out"]["frames"].get<int>());
  EXPECT_NEAR(psnr_sum / images, self["held_out"]["psnr"].get<double>(),
              0.1);
  // Its values per point are the model's own, and the script comparing
  // the two files finds no speed change between them.
  EXPECT_EQ(ReadWholeFile(root / "self_eval" / "motion_gt_reference.csv"),
            ReadWholeFile(root / "self_eval" / "motion_gt.csv"));
  const fs::path script =
      fs::path(ES_SOURCE_DIR) / "scripts" / "motion_speed_scale.py";
  log.clear();
  EXPECT_EQ(RunCommand("python3 " + script.string() + " " +
                           (root / "self_eval").string(),
                       &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("reference x 1.00 (the model's speed)"));
  // A reference that is not there is named before any work.
  const fs::path missing = root / "missing_motion_field.bin";
  EXPECT_NE(eval_with_reference(root / "missing_eval", missing), 0);
  EXPECT_THAT(log, HasSubstr(missing.string()));
  EXPECT_FALSE(fs::exists(root / "missing_eval" / "eval.json"));

  // The fixed-view video loops: frame k and frame k + L are the same image.
  const fs::path frames = out / "animate_fixed" / "frames";
  for (int k = 0; k < 2 * kL; ++k) {
    char a[32], b[32];
    std::snprintf(a, sizeof(a), "frame_%06d.png", k);
    std::snprintf(b, sizeof(b), "frame_%06d.png", k + kL);
    const cv::Mat fa = cv::imread((frames / a).string());
    const cv::Mat fb = cv::imread((frames / b).string());
    ASSERT_FALSE(fa.empty());
    EXPECT_EQ(cv::norm(fa, fb, cv::NORM_INF), 0.0) << "frame " << k;
  }
  const cv::Mat slice =
      cv::imread((out / "animate_fixed" / "xt_slice_raw.png").string());
  EXPECT_EQ(slice.rows, 3 * kL);
  EXPECT_EQ(slice.cols, 64);

  // Everything is done: a second run skips every stage.
  log.clear();
  ASSERT_EQ(RunCommand(driver, &log), 0) << log;
  for (const char* stage : {"[static] skipped", "[flow init] skipped",
                            "[joint] skipped", "[animate] skipped",
                            "[animate_fixed] skipped", "[eval] skipped"}) {
    EXPECT_THAT(log, HasSubstr(stage)) << stage << "\n" << log;
  }
  if (have_viewer) {
    EXPECT_THAT(log, HasSubstr("[export] skipped"));
  }
}

TEST(EndToEndTest, BadPresetIsAClearError) {
  std::string log;
  const int status = RunCommand((kBin / "eulersplat").string() +
                             " --scene /nonexistent --out /tmp/x --preset "
                             "huge",
                         &log);
  EXPECT_EQ(status, 1);
  EXPECT_THAT(log, HasSubstr("unknown preset 'huge'"));
}

}  // namespace
}  // namespace es
