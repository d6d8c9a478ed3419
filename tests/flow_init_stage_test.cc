// Stage 2 as a library (solvers/train/flow_init_stage.h), the code behind
// es_flowinit: a run on a tiny synthetic scene writes its four files,
// replays bit for bit, and flow_metrics.json spells the options as the
// flags do; bad inputs are refused before anything is written.

#include "solvers/train/flow_init_stage.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/base/input_error.h"
#include "core/io/ply_io.h"
#include "solvers/train/flow_init_metrics.h"
#include "synth/scene.h"
#include "synth/writer.h"
#include "tests/temp_dir_test.h"
#include "tests/tiny_synth_settings.h"
#include "tests/whole_file.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

class FlowInitStageTest : public TempDirTest {
 protected:
  // A tiny synthetic scene with ground truth, and as Stage 1's model its
  // scenery plus the water of its first frame, marked dynamic.
  void WriteScene() {
    const SynthSettings s = TinySynthSettings("waterfall", 8);
    GaussianSet water;
    const SynthScene scene =
        GenerateSynthScene(s, [&water](int frame, const GaussianSet& g) {
          if (frame == 0) water = g;
        });
    WriteSynthScene(scene, Path("scene"));
    GaussianSet model = scene.scenery;
    for (double& logit : model.dynamic_logits) logit = -5;
    water.SetShDegree(model.sh_degree);
    for (int i = 0; i < water.size(); ++i) {
      model.AppendFrom(water, i);
      model.dynamic_logits.back() = 5;
    }
    WritePly(model, Path("scene/static.ply"));
  }

  FlowInitStageOptions SmallRun(const std::string& out) const {
    FlowInitStageOptions o;
    o.scene_dir = Path("scene");
    o.out_dir = Path(out);
    o.flow.image = FlowImage::kFrame;
    o.field.triplane.resolution = 8;
    o.field.triplane.channels = 4;
    o.field.mlp_width = 16;
    o.pretrain.iterations = 20;
    o.pretrain.batch_size = 256;
    o.pretrain.log_every = 10;
    return o;
  }
};

TEST_F(FlowInitStageTest, WritesItsFilesAndReplaysBitForBit) {
  WriteScene();
  const FlowInitStageResult a = RunFlowInitStage(SmallRun("a"));
  const FlowInitStageResult b = RunFlowInitStage(SmallRun("b"));
  for (const char* name : {"motion_field.bin", "scene_flow_samples.bin",
                           "flow_history.csv", "flow_metrics.json"}) {
    EXPECT_TRUE(fs::exists(Path("a/") + name)) << name;
  }
  ASSERT_GT(a.fit.num_samples, 0);
  EXPECT_EQ(ReadWholeFile(Path("a/motion_field.bin")),
            ReadWholeFile(Path("b/motion_field.bin")));
  EXPECT_EQ(ReadWholeFile(Path("a/scene_flow_samples.bin")),
            ReadWholeFile(Path("b/scene_flow_samples.bin")));
  EXPECT_EQ(a.fit.fit_rmse, b.fit.fit_rmse);
  // The scene has gt/: V's and the samples' errors against it are written.
  ASSERT_TRUE(a.field_gt && a.samples_gt);
  const nlohmann::json json =
      nlohmann::json::parse(ReadWholeFile(Path("a/flow_metrics.json")));
  EXPECT_EQ(json["num_samples"], a.fit.num_samples);
  EXPECT_EQ(json["num_dynamic"], a.num_dynamic);
  EXPECT_EQ(json["epe_gt"], a.field_gt->epe);
  EXPECT_EQ(json["samples_rel_epe_gt"], a.samples_gt->rel_epe);
}

// Scripts read these fields as the flags' values: each must parse back to
// the option it records.
TEST(FlowMetricsJsonTest, SpellsTheOptionsAsTheFlagsDo) {
  for (FlowImage image : {FlowImage::kFrame, FlowImage::kFluctuation}) {
    for (SecondEnd end : {SecondEnd::kFacingPlane, SecondEnd::kRenderedDepth}) {
      for (PretrainSolver solver : {PretrainSolver::kAdam,
                                    PretrainSolver::kLbfgs,
                                    PretrainSolver::kLm}) {
        FlowInitStageOptions o;
        o.flow.method = FlowMethod::kFarneback;
        o.flow.image = image;
        o.flow.lifting.second_end = end;
        o.flow.lifting.line_of_sight_weight = 0.25;
        o.free_line_of_sight = false;
        o.pretrain.solver = solver;
        o.oracle = TruthPart::kSeen;
        const nlohmann::ordered_json json =
            FlowMetricsJson(o, FlowInitStageResult{});
        EXPECT_EQ(ParseFlowMethod(json["flow"]), o.flow.method);
        EXPECT_EQ(ParseFlowImage(json["flow_image"]), image);
        EXPECT_EQ(ParseSecondEnd(json["second_end"]), end);
        EXPECT_EQ(ParsePretrainSolver(json["solver"]), solver);
        EXPECT_TRUE(ParseOracleVelocity(json["oracle_velocity"]) == o.oracle);
        // The weight as given, beside the switch that overrides it.
        EXPECT_EQ(json["line_of_sight_weight"], 0.25);
        EXPECT_EQ(json["free_line_of_sight"], false);
        EXPECT_FALSE(json.contains("epe_gt"));  // no ground truth measured
      }
    }
  }
}

TEST(FlowInitOptionsTest, OracleVelocitySpellingsRoundTrip) {
  for (const char* name : {"none", "seen", "full"}) {
    EXPECT_EQ(OracleVelocityName(ParseOracleVelocity(name)), name);
  }
  try {
    ParseOracleVelocity("perfect");
    FAIL() << "accepted --oracle_velocity perfect";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("--oracle_velocity"))
        << e.what();
  }
}

TEST_F(FlowInitStageTest, RefusesAnOracleWithoutGroundTruthBeforeWriting) {
  fs::create_directories(Path("scene"));
  FlowInitStageOptions o = SmallRun("out");
  o.oracle = TruthPart::kFull;
  EXPECT_THROW(RunFlowInitStage(o), InputError);
  EXPECT_FALSE(fs::exists(Path("out")));
}

TEST_F(FlowInitStageTest, RefusesAModelWithoutWaterAndWritesNothing) {
  WriteScene();
  GaussianSet model = ReadPly(Path("scene/static.ply"));
  for (double& logit : model.dynamic_logits) logit = -5;
  WritePly(model, Path("scene/static.ply"));
  try {
    RunFlowInitStage(SmallRun("out"));
    FAIL() << "pretrained V on a model without water";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("no dynamic Gaussians"))
        << e.what();
  }
  EXPECT_FALSE(fs::exists(Path("out/motion_field.bin")));
  EXPECT_FALSE(fs::exists(Path("out/flow_metrics.json")));
}

}  // namespace
}  // namespace es
