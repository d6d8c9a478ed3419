// Stress cases for the trainers: degenerate Gaussians (huge, zero scales;
// opacity logits of +/-1e6; zero quaternions), absurd learning rates,
// all-black and all-white frames, a loop of length 1 and zero iterations.
// Whatever happens, a run either ends with a finite model or stops with
// TrainingDiverged; it never crashes and never holds a NaN.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/gaussians.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/static_trainer.h"
#include "tests/centered_camera.h"
#include "tests/small_fields.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

constexpr int kWidth = 32, kHeight = 24;

Camera CameraAt(double x) {
  Camera c = CenteredCamera(kWidth, kHeight, 30);
  c.t_cw = Eigen::Vector3d(-x, 0, 3);  // looking down +z at the origin
  return c;
}

// 60 Gaussians in a slab; the right half is marked dynamic.
GaussianSet SlabGaussians() {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  GaussianSet g;
  g.Resize(60);
  for (int i = 0; i < 60; ++i) {
    g.means[3 * i] = u(rng);
    g.means[3 * i + 1] = 0.7 * u(rng);
    g.means[3 * i + 2] = 0.1 * u(rng);
    for (int a = 0; a < 3; ++a) g.log_scales[3 * i + a] = std::log(0.15);
    g.opacity_logits[i] = Logit(0.7);
    for (int c = 0; c < 3; ++c) g.sh[3 * i + c] = 0.8 * u(rng);
    g.dynamic_logits[i] = g.means[3 * i] > 0 ? 3.0 : -3.0;
  }
  return g;
}

// Frames rendered from the slab (or filled with `fill` when >= 0).
std::vector<Frame> Frames(double fill = -1) {
  const GaussianSet g = SlabGaussians();
  Rasterizer rasterizer;
  RenderResult render;
  std::vector<Frame> frames;
  for (int k = 0; k < 6; ++k) {
    Frame f;
    f.camera = CameraAt(0.1 * k - 0.25);
    f.time_index = k;
    if (fill >= 0) {
      f.image = cv::Mat(kHeight, kWidth, CV_32FC3, cv::Scalar::all(fill));
    } else {
      rasterizer.Forward(f.camera, SplatView::Of(g), RenderOptions(), &render);
      cv::Mat(kHeight, kWidth, CV_64FC3, render.rgb.data())
          .convertTo(f.image, CV_32F);
    }
    frames.push_back(f);
  }
  return frames;
}

const std::vector<int> kTrain = {0, 1, 2, 3, 4, 5};

StaticTrainerOptions StaticOptions() {
  StaticTrainerOptions o;
  o.iterations = 30;
  o.max_sh_degree = 1;
  o.sh_degree_interval = 10;
  o.densify_options.from_iteration = 5;
  o.densify_options.interval = 5;
  o.densify_options.until_iteration = 30;
  o.densify_options.max_gaussians = 200;
  return o;
}

JointTrainerOptions JointOptions() {
  JointTrainerOptions o;
  o.iterations = 12;
  o.cycle_length = 3;
  o.mask_weight = 0;
  SetFieldSize(4, 2, 8, &o.motion);
  SetFieldSize(4, 2, 8, &o.residual);
  o.refresh_interval = 4;
  return o;
}

// Runs a Stage-1 trainer to the end; the model must be finite unless the
// run stopped with TrainingDiverged (how far it got is returned).
int64_t RunStatic(const std::vector<Frame>& frames,
                  const StaticTrainerOptions& options,
                  const GaussianSet& initial, const std::string& what) {
  StaticTrainer trainer(&frames, kTrain, options, initial);
  try {
    while (trainer.iteration() < options.iterations) trainer.Step();
  } catch (const TrainingDiverged&) {
    return trainer.iteration();
  }
  EXPECT_TRUE(AllFinite(trainer.gaussians())) << what;
  return trainer.iteration();
}

int64_t RunJoint(const std::vector<Frame>& frames,
                 const JointTrainerOptions& options,
                 const GaussianSet& initial, const std::string& what) {
  JointTrainer trainer(&frames, kTrain, options, initial, std::nullopt);
  try {
    while (trainer.iteration() < options.iterations) trainer.Step();
  } catch (const TrainingDiverged&) {
    return trainer.iteration();
  }
  const LoopModel& m = trainer.model();
  EXPECT_TRUE(AllFinite(m.gaussians)) << what;
  EXPECT_TRUE(AllFinite(m.motion->params().triplane,
                        m.motion->triplane().num_params()))
      << what;
  EXPECT_TRUE(
      AllFinite(m.residual->params().mlp, m.residual->mlp().num_params()))
      << what;
  return trainer.iteration();
}

TEST(StressTest, DegenerateGaussiansNeverCrashOrGoNan) {
  const std::vector<Frame> frames = Frames();
  struct Case {
    const char* name;
    void (*apply)(GaussianSet*);
  };
  const Case cases[] = {
      {"huge scales", [](GaussianSet* g) {
         for (double& s : g->log_scales) s = 40;
       }},
      {"zero scales", [](GaussianSet* g) {
         for (double& s : g->log_scales) s = -60;
       }},
      {"opacity logit +1e6", [](GaussianSet* g) {
         for (double& o : g->opacity_logits) o = 1e6;
       }},
      {"opacity logit -1e6", [](GaussianSet* g) {
         for (double& o : g->opacity_logits) o = -1e6;
       }},
      {"zero quaternions", [](GaussianSet* g) {
         for (double& q : g->quats) q = 0;
       }},
      {"all at one point", [](GaussianSet* g) {
         for (double& x : g->means) x = 0;
       }},
  };
  for (const Case& c : cases) {
    GaussianSet g = SlabGaussians();
    c.apply(&g);
    RunStatic(frames, StaticOptions(), g, c.name);
    RunJoint(frames, JointOptions(), g, c.name);
  }
}

TEST(StressTest, AbsurdLearningRatesEndFiniteOrStop) {
  const std::vector<Frame> frames = Frames();
  for (double lr : {1e3, 1e12, 1e300}) {
    StaticTrainerOptions s = StaticOptions();
    SplatLearningRateOptions& r = s.splat_lr;
    r.means_initial = r.means_final = r.log_scales = r.quats = r.opacity =
        r.sh_dc = r.sh_rest = lr;
    RunStatic(frames, s, SlabGaussians(), "static lr " + std::to_string(lr));
    JointTrainerOptions j = JointOptions();
    j.splat_lr.means_initial = j.splat_lr.means_final =
        j.splat_lr.log_scales = j.splat_lr.opacity = j.lr_motion_triplane =
            j.lr_motion_mlp = j.lr_residual_triplane = j.lr_residual_mlp = lr;
    RunJoint(frames, j, SlabGaussians(), "joint lr " + std::to_string(lr));
  }
}

TEST(StressTest, BlackAndWhiteFramesTrainFinitely) {
  for (double fill : {0.0, 1.0}) {
    const std::vector<Frame> frames = Frames(fill);
    const std::string what = fill == 0 ? "black" : "white";
    EXPECT_EQ(RunStatic(frames, StaticOptions(), SlabGaussians(), what), 30)
        << what;
    EXPECT_EQ(RunJoint(frames, JointOptions(), SlabGaussians(), what), 12)
        << what;
  }
}

class StressDirTest : public TempDirTest {};

// Cycle length 1 (every frame is the loop's only frame) trains, and a run
// of zero iterations saves a model that loads back.
TEST_F(StressDirTest, CycleLengthOneAndZeroIterations) {
  const std::vector<Frame> frames = Frames();
  JointTrainerOptions one = JointOptions();
  one.cycle_length = 1;
  EXPECT_EQ(RunJoint(frames, one, SlabGaussians(), "L = 1"), 12);

  JointTrainerOptions zero = JointOptions();
  zero.iterations = 0;
  JointTrainer trainer(&frames, kTrain, zero, SlabGaussians(), std::nullopt);
  SaveLoopModel(trainer.model(), Path("model"));
  const LoopModel loaded = LoadLoopModel(Path("model"));
  EXPECT_EQ(loaded.gaussians.size(), 60);
  EXPECT_EQ(loaded.num_dynamic(), trainer.model().num_dynamic());
}

}  // namespace
}  // namespace es
