// RunJointStage, Stage 3 as es_train runs it, on a tiny synthetic scene: a
// complete run writes the files the driver (eulersplat) checks, in
// agreement with its result; a run that fails on its last write does not
// look done to the driver (StagePlan::JointStep's outputs), so the driver
// runs the stage again, and the rerun finishes it.

#include "solvers/train/joint_stage.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/base/input_error.h"
#include "core/io/csv_table.h"
#include "core/io/ply_io.h"
#include "core/io/scene.h"
#include "core/model/gaussian_init.h"
#include "solvers/pipeline/stage_plan.h"
#include "synth/scene.h"
#include "synth/writer.h"
#include "tests/small_fields.h"
#include "tests/temp_dir_test.h"
#include "tests/tiny_synth_settings.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr int kIterations = 6;

class JointStageTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    WriteSynthScene(GenerateSynthScene(TinySynthSettings()), Path("scene"));
    // A static model with every third Gaussian water, so V and D have a
    // dynamic set to move.
    const Scene scene = LoadScene(Path("scene"), SceneOptions());
    GaussianSet g =
        InitGaussiansFromPoints(scene.points, scene.point_colors, 0);
    for (int i = 0; i < g.size(); ++i)
      g.dynamic_logits[i] = i % 3 == 0 ? 3.0 : -3.0;
    fs::create_directories(Path("init"));
    WritePly(g, Path("init/static.ply"));
  }

  // Stage 3 as the driver runs it in a run folder: its outputs all
  // present means done.
  StageStep DriversJointStep() const {
    PipelineOptions run;
    run.out = Path("run");
    return StagePlan(run).JointStep();
  }

  JointStageOptions Options() const {
    JointStageOptions o;
    o.scene_dir = Path("scene");
    o.init_dir = Path("init");
    o.out_dir = Path("run/model");  // where the driver has es_train write
    o.log_interval = 0;  // history.csv is written only at the end
    o.eval_interval = 0;
    o.checkpoint_interval = kIterations;
    JointTrainerOptions& t = o.trainer;
    t.iterations = kIterations;
    t.cycle_length = 4;
    SetFieldSize(8, 4, 16, &t.motion);
    SetFieldSize(8, 4, 16, &t.residual);
    return o;
  }

  nlohmann::json Metrics() const {
    std::ifstream in(Path("run/model/metrics.json"));
    return nlohmann::json::parse(in);
  }
};

TEST_F(JointStageTest, CompleteRunWritesWhatTheDriverChecks) {
  const JointStageResult r = RunJointStage(Options());
  EXPECT_EQ(r.iterations, kIterations);
  EXPECT_FALSE(r.flow_init);  // init/ has no motion_field.bin
  EXPECT_GT(r.num_dynamic, 0);
  EXPECT_TRUE(std::isfinite(r.test.psnr));
  EXPECT_GT(r.test.frames, 0);
  ASSERT_TRUE(StepIsDone(DriversJointStep()));
  const nlohmann::json m = Metrics();
  EXPECT_DOUBLE_EQ(m["psnr_test"].get<double>(), r.test.psnr);
  EXPECT_EQ(m["iterations"].get<int>(), kIterations);
  EXPECT_EQ(m["num_gaussians"].get<int>(), r.num_gaussians);
  EXPECT_EQ(m["num_dynamic"].get<int>(), r.num_dynamic);
  // The history's last row is the end, with the same held-out PSNR (to
  // the 9 significant digits history.csv keeps).
  const CsvTable history = ReadCsvTable(Path("run/model/history.csv"));
  ASSERT_FALSE(history.rows.empty());
  EXPECT_EQ(history.rows.back()[0], kIterations);
  EXPECT_NEAR(history.rows.back()[history.Column("psnr_test")], r.test.psnr,
              1e-6);
}

TEST_F(JointStageTest, FailedHistoryWriteLeavesTheStageUndone) {
  // A directory where history.csv goes: its one write, at the end, fails.
  fs::create_directories(Path("run/model/history.csv/blocker"));
  try {
    RunJointStage(Options());
    FAIL() << "the history write did not fail";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("history.csv")) << e.what();
  }
  // The run got to its end (the model is written) but the driver does not
  // take the stage as done.
  EXPECT_TRUE(fs::exists(Path("run/model/loop.txt")));
  EXPECT_FALSE(StepIsDone(DriversJointStep()));

  // The driver's rerun (--resume) continues from the last checkpoint and
  // finishes the stage.
  fs::remove_all(Path("run/model/history.csv"));
  JointStageOptions o = Options();
  o.resume = true;
  const JointStageResult r = RunJointStage(o);
  EXPECT_EQ(r.iterations, kIterations);
  ASSERT_TRUE(StepIsDone(DriversJointStep()));
  EXPECT_DOUBLE_EQ(Metrics()["psnr_test"].get<double>(), r.test.psnr);
  EXPECT_EQ(ReadCsvTable(Path("run/model/history.csv")).rows.back()[0],
            kIterations);
}

}  // namespace
}  // namespace es
