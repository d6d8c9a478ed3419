// --preset auto (solvers/pipeline/preset_choice.h): the README's scene
// gets exactly quick on any machine, a big clip on two cores a narrower
// quick that the time model says fits ten minutes, a GPU the paper preset;
// a named preset is run as named and an unknown one is refused by name.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "core/base/input_error.h"
#include "solvers/pipeline/preset_choice.h"
#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;
using ::testing::Not;

namespace es {
namespace {

namespace fs = std::filesystem;

void ExpectSamePreset(const Preset& a, const Preset& b) {
  EXPECT_EQ(a.static_iterations, b.static_iterations);
  EXPECT_EQ(a.flow_iterations, b.flow_iterations);
  EXPECT_EQ(a.joint_iterations, b.joint_iterations);
  EXPECT_EQ(a.motion_resolution, b.motion_resolution);
  EXPECT_EQ(a.residual_resolution, b.residual_resolution);
  EXPECT_EQ(a.motion_channels, b.motion_channels);
  EXPECT_EQ(a.residual_channels, b.residual_channels);
  EXPECT_EQ(a.motion_width, b.motion_width);
  EXPECT_EQ(a.residual_width, b.residual_width);
  EXPECT_EQ(a.max_width, b.max_width);
  EXPECT_EQ(a.sh_degree, b.sh_degree);
  EXPECT_EQ(a.densify_from, b.densify_from);
  EXPECT_EQ(a.densify_interval, b.densify_interval);
}

const ClipSize kReadmeClip = {60, 160, 120};  // scripts/run_default.sh
const ClipSize kUserClip = {120, 320, 240};   // the phone clip

TEST(PresetTest, TheReadmeSceneGetsExactlyQuickOnAnyCpu) {
  for (int threads : {1, 2, 16}) {
    const PresetChoice c =
        ChoosePreset(kReadmeClip, PipelineOptions(), {threads, false});
    EXPECT_EQ(c.name, "quick") << threads;
    ExpectSamePreset(c.preset, MakePreset("quick"));
    EXPECT_THAT(c.why, Not(HasSubstr(" px wide")));
  }
}

TEST(PresetTest, ABigClipOnTwoCoresTrainsNarrowerWithinTheTarget) {
  const Hardware two = {2, false};
  const PresetChoice c = ChoosePreset(kUserClip, PipelineOptions(), two);
  EXPECT_EQ(c.name, "quick");
  EXPECT_LT(c.preset.max_width, 320) << c.why;
  EXPECT_GE(c.preset.max_width, 160) << c.why;
  EXPECT_LE(c.predicted_seconds, TargetSeconds(two)) << c.why;
  EXPECT_THAT(c.why,
              HasSubstr(std::to_string(c.preset.max_width) + " px wide"));
  // The widest that fits: one step wider does not.
  const std::vector<int> widths = {320, 288, 256, 224, 208, 192, 176, 160};
  const auto at = std::find(widths.begin(), widths.end(), c.preset.max_width);
  ASSERT_TRUE(at != widths.end() && at != widths.begin()) << c.why;
  Preset wider = c.preset;
  wider.max_width = *(at - 1);
  EXPECT_GT(PredictSeconds(MeasuredTimeModel(), wider, kUserClip, 15, two),
            TargetSeconds(two));
  // Only the width changed: the rest is quick's.
  Preset expected = MakePreset("quick");
  expected.max_width = c.preset.max_width;
  ExpectSamePreset(c.preset, expected);
}

TEST(PresetTest, MoreThreadsNeverTrainNarrower) {
  int previous = 0;
  for (int threads : {1, 2, 4, 8, 32}) {
    const PresetChoice c =
        ChoosePreset(kUserClip, PipelineOptions(), {threads, false});
    EXPECT_GE(c.preset.max_width, previous) << threads << ": " << c.why;
    previous = c.preset.max_width;
  }
  EXPECT_EQ(previous, 320) << "32 threads run the whole quick preset";
}

// A clip too big for any quick run still gets the narrowest, and says so.
TEST(PresetTest, AClipTooBigForTheTargetGetsTheNarrowestAndSaysSo) {
  TimeModel slow = MeasuredTimeModel();  // a machine 100x slower
  slow.static_seconds *= 100;
  slow.joint_seconds *= 100;
  slow.frame_seconds *= 100;
  const PresetChoice c =
      ChoosePreset({300, 1920, 1080}, PipelineOptions(), {1, false}, slow);
  EXPECT_EQ(c.preset.max_width, 160);
  EXPECT_GT(c.predicted_seconds, 600);
  EXPECT_THAT(c.why, HasSubstr("no quick run is predicted to fit"));
}

TEST(PresetTest, AGpuRunsThePaperPresetWhereItFitsTheHour) {
  const PresetChoice c =
      ChoosePreset({200, 1168, 880}, PipelineOptions(), {16, true});
  EXPECT_EQ(c.name, "paper") << c.why;
  ExpectSamePreset(c.preset, MakePreset("paper"));
  EXPECT_LE(c.predicted_seconds, 3600);
}

// The user's iteration overrides are part of what is predicted and run.
TEST(PresetTest, OverridesArePredictedAndKept) {
  PipelineOptions o;
  o.joint_iterations = 100;
  const PresetChoice c = ChoosePreset(kUserClip, o, {2, false});
  EXPECT_EQ(c.preset.joint_iterations, 100);
  EXPECT_EQ(c.preset.max_width, 320) << "100 joint iterations fit: " << c.why;
}

TEST(PresetTest, PresetNames) {
  EXPECT_NO_THROW(CheckPresetName("auto"));
  EXPECT_NO_THROW(CheckPresetName("quick"));
  EXPECT_NO_THROW(CheckPresetName("paper"));
  EXPECT_THROW(CheckPresetName("fast"), InputError);
  EXPECT_THROW(MakePreset("auto"), InputError) << "auto needs the clip";
}

// The driver: an unknown preset is refused by name before any work; a
// named one runs as named, with no choice made (a tiny run, no videos).
TEST(PresetTest, TheDriverRunsANamedPresetAndRefusesAnUnknownOne) {
  std::string log;
  const fs::path root = MakeTinyDriverScene("preset_test", &log);
  ASSERT_FALSE(root.empty()) << log;
  const fs::path scene = root / "scene", out = root / "out";
  const std::string driver = (kBin / "eulersplat").string() + " --scene " +
                             scene.string() + " --out " + out.string() +
                             " --cycle_length 4";
  log.clear();
  EXPECT_EQ(RunCommand(driver + " --preset fast", &log), 1) << log;
  EXPECT_THAT(log, HasSubstr("--preset: unknown preset 'fast' (auto, quick or "
                             "paper)"));
  EXPECT_FALSE(fs::exists(out)) << "work started anyway";

  log.clear();
  ASSERT_EQ(RunCommand(driver + " --preset paper --static_iterations 2 "
                                "--flow_iterations 0 --joint_iterations 2 "
                                "--animate=false",
                       &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("preset paper: 2 static / 0 flow / 2 joint"));
  EXPECT_THAT(log, Not(HasSubstr("--preset auto chose")));
  const std::string timings = ReadWholeFile(out / "timings.json");
  EXPECT_THAT(timings, HasSubstr("\"preset\": \"paper\""));
  EXPECT_THAT(timings, Not(HasSubstr("preset_auto")));
  fs::remove_all(root);
}

}  // namespace
}  // namespace es
