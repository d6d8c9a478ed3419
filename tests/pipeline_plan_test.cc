// The driver's plan without running a stage: the flags each stage binary
// gets from the options and the preset, when a stage is skipped or
// resumed, and how the stage runner passes --device on.

#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "solvers/pipeline/stage_plan.h"
#include "solvers/pipeline/stage_process.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;
using Args = std::vector<std::string>;

// The value after `flag` in `args` ("" when absent).
std::string Value(const Args& args, const std::string& flag) {
  for (size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == flag) return args[i + 1];
  }
  return "";
}

PipelineOptions Options(const std::string& out) {
  PipelineOptions o;
  o.scene = "/scene";
  o.out = out;
  return o;
}

TEST(PipelinePlanTest, QuickJointFlagsWithOverridesAndExtraFlags) {
  PipelineOptions o = Options("/o");
  o.joint_iterations = 120;
  o.cycle_length = 10;
  o.white_background = true;
  o.train_flags = "--no_residual  --seed 3";
  StagePlan plan(o);
  plan.SetScene("/s", 0.5);
  const StageStep joint = plan.JointStep();
  EXPECT_EQ(joint.binary, "es_train");
  EXPECT_EQ(joint.args,
            (Args{"--scene", "/s", "--image_scale", "0.5", "--init",
                  "/o/static", "--out", "/o/model", "--iterations", "120",
                  "--cycle_length", "10", "--resume", "--dynamic_threshold",
                  "0.2", "--motion_resolution", "32", "--motion_channels",
                  "8", "--motion_width", "32", "--residual_resolution", "64",
                  "--residual_channels", "16", "--residual_width", "128",
                  "--checkpoint_interval", "20", "--log_interval", "6",
                  "--eval_interval", "24", "--white_background",
                  "--mask_weight", "0", "--no_residual", "--seed", "3"}));
  EXPECT_EQ(joint.outputs, (std::vector<fs::path>{"/o/model/loop.txt",
                                                  "/o/model/metrics.json"}));
  EXPECT_TRUE(joint.on_failure.empty()) << "a failed Stage 3 must stop";
  // Stage 2 is not fatal, and the preset's other lengths stay.
  const StageStep flow = plan.FlowStep();
  EXPECT_FALSE(flow.on_failure.empty());
  EXPECT_EQ(Value(flow.args, "--iterations"), "300");
  EXPECT_EQ(Value(flow.args, "--log_every"), "15");
}

TEST(PipelinePlanTest, PaperStaticFlagsInASharedStaticFolder) {
  PipelineOptions o = Options("/o");
  o.preset = "paper";
  o.static_dir = "/shared";
  StagePlan plan(o);
  plan.SetScene("/s", 1);
  plan.SetHasMasks(true);
  EXPECT_EQ(plan.StaticStep().args,
            (Args{"--out", "/shared", "--iterations", "10000", "--scene",
                  "/s", "--image_scale", "1", "--sh_degree", "3",
                  "--sh_degree_interval", "2500", "--densify_from", "500",
                  "--densify_interval", "100", "--dynamic_threshold", "0.2",
                  "--checkpoint_every", "1000", "--log_every", "100",
                  "--eval_every", "2000"}));
  const MaskProbe probe = plan.MaskProbeSettings();
  EXPECT_EQ(probe.iterations, 5000);  // half of Stage 1
  EXPECT_EQ(probe.mask_flags, (Args{"--scene", "/s", "--image_scale", "1"}));
  EXPECT_EQ(plan.FlowStep().where, fs::path("/shared"));
}

TEST(PipelinePlanTest, UnknownPresetIsRefused) {
  PipelineOptions o = Options("/o");
  o.preset = "fast";
  EXPECT_THROW(StagePlan{o}, InputError);
}

class PipelinePlanFilesTest : public TempDirTest {};

TEST_F(PipelinePlanFilesTest, StagesSkipOnlyWhenAllOutputsExistAndResume) {
  StagePlan plan(Options(dir_.string()));
  plan.SetScene("/s", 1);
  const fs::path stat = dir_ / "static";
  fs::create_directories(stat);
  EXPECT_FALSE(StepIsDone(plan.StaticStep()));
  EXPECT_EQ(plan.StaticStep().args.back(), "0");  // --mask_weight 0
  std::ofstream(stat / "checkpoint.bin") << "x";
  EXPECT_EQ(plan.StaticStep().args.back(), "--resume");
  std::ofstream(stat / "static.ply") << "x";
  EXPECT_FALSE(StepIsDone(plan.StaticStep())) << "metrics.json is missing";
  std::ofstream(stat / "metrics.json") << "{}";
  EXPECT_TRUE(StepIsDone(plan.StaticStep()));
  EXPECT_FALSE(StepIsDone(plan.FlowStep()));

  // es_eval compares with Stage 2's V only when there is one.
  const Args before = plan.EvalStep().args;
  std::ofstream(stat / "motion_field.bin") << "x";
  const Args after = plan.EvalStep().args;
  ASSERT_EQ(after.size(), before.size() + 2);
  EXPECT_EQ(after[after.size() - 1], (stat / "motion_field.bin").string());
  EXPECT_EQ(after[after.size() - 2], "--reference_motion");

  // Plots only for the histories that exist.
  EXPECT_TRUE(plan.PlotRuns().empty());
  std::ofstream(stat / "history.csv") << "x";
  ASSERT_EQ(plan.PlotRuns().size(), 1u);
  EXPECT_EQ(plan.PlotRuns()[0].second,
            (Args{"--history", (stat / "history.csv").string(), "--out",
                  (dir_ / "plots").string(), "--prefix", "static_"}));
}

TEST(PipelinePlanTest, TracksVideoRendersOnTheCpuWhenTheStagesUseAGpu) {
  PipelineOptions o = Options("/o");
  o.device = "cuda";
  o.cycle_length = 6;
  StagePlan plan(o);
  plan.SetScene("/s", 1);
  const std::vector<StageStep> videos = plan.AnimateSteps();
  ASSERT_EQ(videos.size(), 2u);
  EXPECT_EQ(videos[0].args,
            (Args{"--scene", "/s", "--image_scale", "1", "--model",
                  "/o/model", "--frames", "24", "--out", "/o/animate",
                  "--camera", "input", "--tracks", "--device", "cpu"}));
  EXPECT_FALSE(videos[0].note.empty());
  EXPECT_EQ(videos[1].args.back(), "auto");  // --xt_slice, on the GPU
  EXPECT_TRUE(videos[1].note.empty());
}

TEST(StageProcessRunnerTest, PassesDeviceToTheStagesThatTakeIt) {
  std::vector<std::pair<std::string, Args>> launched;
  int status = 0;
  const StageProcessRunner runner(
      "cuda", "/bin_dir", [&](const std::string& path, const Args& args) {
        launched.emplace_back(path, args);
        return status;
      });
  EXPECT_EQ(runner.Run("es_train", {"--x"}), 0);
  runner.Run("es_plot", {"--x"});
  runner.Run("es_animate", {"--device", "cpu"});
  runner.Run("/bin/bash", {"script.sh"});
  ASSERT_EQ(launched.size(), 4u);
  EXPECT_EQ(launched[0].first, "/bin_dir/es_train");
  EXPECT_EQ(launched[0].second, (Args{"--x", "--device", "cuda"}));
  EXPECT_EQ(launched[1].second, (Args{"--x"}));
  EXPECT_EQ(launched[2].second, (Args{"--device", "cpu"}));
  EXPECT_EQ(launched[3].first, "/bin/bash");
  status = 3;
  try {
    runner.RunOrThrow("[joint]", "es_train", {});
    FAIL() << "a failed stage must throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "[joint] failed (es_train exit status 3; its message is "
                 "above)");
  }
}

TEST(StageProcessRunnerTest, RunsTheTrainingStagesUnderMpiexec) {
  std::vector<std::pair<std::string, Args>> launched;
  StageProcessRunner runner(
      "cpu", "/bin_dir", [&](const std::string& path, const Args& args) {
        launched.emplace_back(path, args);
        return 0;
      });
  RankLaunch ranks;
  ranks.ranks = 2;
  ranks.batch_frames = 4;
  ranks.mpiexec = "/usr/bin/mpiexec";
  ranks.threads_per_rank = 1;
  runner.SetRanks(ranks);
  runner.Run("es_static", {"--x"});
  runner.Run("es_train", {"--batch_frames", "6"});  // the caller's batch
  runner.Run("es_flowinit", {"--x"});  // ranks, but no frame batches
  runner.Run("es_eval", {"--x"});      // not data-parallel: as before
  ASSERT_EQ(launched.size(), 4u);
  EXPECT_EQ(launched[0].first, "/usr/bin/mpiexec");
  EXPECT_EQ(launched[0].second,
            (Args{"-n", "2", "-x", "OMP_NUM_THREADS=1", "/bin_dir/es_static",
                  "--x", "--device", "cpu", "--batch_frames", "4"}));
  EXPECT_EQ(launched[1].second,
            (Args{"-n", "2", "-x", "OMP_NUM_THREADS=1", "/bin_dir/es_train",
                  "--batch_frames", "6", "--device", "cpu"}));
  EXPECT_EQ(launched[2].first, "/usr/bin/mpiexec");
  EXPECT_EQ(launched[2].second,
            (Args{"-n", "2", "-x", "OMP_NUM_THREADS=1",
                  "/bin_dir/es_flowinit", "--x", "--device", "cpu"}));
  EXPECT_EQ(launched[3].first, "/bin_dir/es_eval");
  EXPECT_EQ(launched[3].second, (Args{"--x", "--device", "cpu"}));
}

}  // namespace
}  // namespace es
