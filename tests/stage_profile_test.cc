// --profile by part (core/base/iteration_parts.h) and the driver's
// OUT/timings.json: the parts of a profiled training add up to the time
// the iterations took, renders are charged to the pass they were made
// for, and the driver's stages tile its run.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/base/iteration_parts.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/train/joint_trainer.h"
#include "tests/pipeline_test_util.h"
#include "tests/tiny_loop_scene.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;
using namespace tiny_loop;  // NOLINT: the scene's constants

double SumOfParts(const StageProfile& profile) {
  double sum = 0;
  for (int k = 0; k < static_cast<int>(Part::kNumParts); ++k)
    sum += PartSeconds(profile, Part(k));
  return sum;
}

// Profiling stays on for the test's scope only (it is process-wide).
class StageProfileTest : public ::testing::Test {
 protected:
  void SetUp() override { StageProfile::Get().Start(true); }
  void TearDown() override { StageProfile::Get().Start(false); }
};

// Joint steps with the loop texture and the pair texture terms on: the
// parts add up to the steps' wall time (nothing counted twice, little
// missed), and each part the step has shows time.
TEST_F(StageProfileTest, PartsAddUpToTheIterationTime) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.iterations = 30;
  options.random_start = true;
  options.loop_texture_weight = 0.5;
  JointTrainer trainer(&frames, {0, 1, 2, 4, 5, 7, 8, 9, 10}, options,
                       TrueCanonical(), std::nullopt);
  StageProfile::Get().Start(true);  // not the trainer's setup
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < options.iterations; ++i) trainer.Step();
  const double wall = std::chrono::duration<double>(
                          std::chrono::steady_clock::now() - start)
                          .count();
  const StageProfile& profile = StageProfile::Get();
  EXPECT_EQ(profile.calls(Stage::kIteration), options.iterations);
  const double sum = SumOfParts(profile);
  EXPECT_LE(sum, wall);
  EXPECT_GE(sum, 0.9 * wall) << PartsTable(profile);
  for (Part part : {Part::kFitRender, Part::kLoopTextureRender,
                    Part::kFields, Part::kBackward, Part::kAdam}) {
    EXPECT_GT(PartSeconds(profile, part), 0) << PartName(part);
  }
  EXPECT_EQ(PartSeconds(profile, Part::kEvaluation), 0);
  const std::string table = PartsTable(profile);
  EXPECT_THAT(table, HasSubstr("loop texture render + loss"));
  EXPECT_THAT(table, HasSubstr("the loop texture pass in all"));
}

// The same renders in an evaluation pass go to the evaluation, not to the
// fit: the rasterizer's stages are told apart by the pass around them.
TEST_F(StageProfileTest, RendersAreChargedToTheirPass) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainer trainer(&frames, {0, 1, 2}, TinyOptions(), TrueCanonical(),
                       std::nullopt);
  StageProfile::Get().Start(true);
  {
    ScopedPass pass(Pass::kEvaluation);
    ScopedStage timer(Stage::kEvaluation);
    EvaluateLoopModel(trainer.model(), frames, {3, 6},
                      trainer.render_options());
  }
  const StageProfile& profile = StageProfile::Get();
  EXPECT_GT(profile.nanoseconds(Stage::kProjection, Pass::kEvaluation), 0);
  EXPECT_EQ(profile.nanoseconds(Stage::kProjection, Pass::kFit), 0);
  EXPECT_EQ(PartSeconds(profile, Part::kFitRender), 0);
  EXPECT_GT(PartSeconds(profile, Part::kEvaluation), 0);
  EXPECT_EQ(profile.pass(), Pass::kFit) << "the pass before comes back";
}

TEST(StagePartsTest, EveryStageOfEveryPassHasOnePart) {
  for (int p = 0; p < static_cast<int>(Pass::kNumPasses); ++p) {
    for (int s = 0; s < static_cast<int>(Stage::kNumStages); ++s) {
      const Part part = PartOf(Pass(p), Stage(s));
      EXPECT_LT(static_cast<int>(part), static_cast<int>(Part::kNumParts));
    }
  }
  EXPECT_EQ(PartOf(Pass::kLoopTexture, Stage::kForwardTiles),
            Part::kLoopTextureRender);
  EXPECT_EQ(PartOf(Pass::kFit, Stage::kForwardTiles), Part::kFitRender);
  EXPECT_EQ(PartOf(Pass::kLoopTexture, Stage::kBackwardTiles),
            Part::kBackward);
  EXPECT_EQ(PartOf(Pass::kDensify, Stage::kProjection), Part::kDensification);
}

// A tiny driver run with --profile: OUT/timings.json lists the stages in
// the order they ran, their seconds add up to the run's, and es_static and
// es_train print their parts; --preset auto (the default) chose quick for
// this small clip and says why.
TEST(DriverTimingsTest, TimingsJsonTilesTheRun) {
  std::string log;
  const fs::path root = MakeTinyDriverScene("stage_profile_test", &log);
  ASSERT_FALSE(root.empty()) << log;
  const fs::path scene = root / "scene", out = root / "out";
  log.clear();
  ASSERT_EQ(RunCommand((kBin / "eulersplat").string() + " --scene " +
                           scene.string() + " --out " + out.string() +
                           kFewIterationsFlags + " --profile",
                       &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("--preset auto chose quick: 8 frames of 32x24"));
  EXPECT_THAT(log, HasSubstr("profile: es_static"));
  EXPECT_THAT(log, HasSubstr("profile: es_train"));
  size_t parts = 0;
  for (size_t at = 0; (at = log.find("profile by part:", at)) !=
                      std::string::npos;
       ++at)
    ++parts;
  EXPECT_EQ(parts, 2u) << log;

  const nlohmann::json t =
      nlohmann::json::parse(ReadWholeFile(out / "timings.json"));
  EXPECT_EQ(t["preset"], "quick");
  EXPECT_TRUE(t.contains("preset_auto"));
  const std::vector<std::string> expected = {
      "frames, poses and masks",
      "static model (es_static)",
      "motion field from optical flow (es_flowinit)",
      "joint training of the loop (es_train)",
      "web page and frame PLY (es_export)",
      "evaluation (es_eval)",
      "training plots (es_plot)"};
  ASSERT_EQ(t["stages"].size(), expected.size()) << t.dump(2);
  double sum = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    const nlohmann::json& s = t["stages"][i];
    EXPECT_EQ(s["name"], expected[i]);
    EXPECT_FALSE(s["skipped"].get<bool>());
    EXPECT_GE(s["seconds"].get<double>(), 0);
    EXPECT_GE(s["cpu_seconds"].get<double>(), 0);
    sum += s["seconds"].get<double>();
  }
  EXPECT_GT(t["stages"][3]["cpu_seconds"].get<double>(), 0)
      << "es_train's CPU time is counted";
  const double total = t["total_seconds"].get<double>();
  EXPECT_LE(sum, total + 1e-6);
  EXPECT_GE(sum, 0.97 * total) << t.dump(2);
  fs::remove_all(root);
}

}  // namespace
}  // namespace es
