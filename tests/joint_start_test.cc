// Stage 3 starts where Stage 1 ends: with V = 0, D = 0 and no particle
// split, the joint trainer's model at iteration 0 renders every frame as
// the static model does. A drop in the water's fidelity at the start of
// Stage 3 is then the motion's or the losses', never the hand-over's.

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "core/fields/motion_field.h"
#include "core/render/image_rasterizer.h"
#include "core/render/rasterizer.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/joint_training_steps.h"
#include "tests/tiny_loop_scene.h"

namespace es {
namespace {

using namespace tiny_loop;  // NOLINT: the scene's constants

const std::vector<int> kTrain = {0, 1, 2, 4, 5, 7, 8, 9, 10};
const std::vector<int> kFrames = {0, 3, 6, 11};

void ZeroField(std::vector<double>* triplane, std::vector<double>* mlp) {
  std::fill(triplane->begin(), triplane->end(), 0.0);
  std::fill(mlp->begin(), mlp->end(), 0.0);
}

// The static model's renders of kFrames, CV_64FC3 RGB.
std::vector<cv::Mat> StaticRenders(const GaussianSet& gaussians,
                                   const std::vector<Frame>& frames,
                                   const RenderOptions& options) {
  Rasterizer rasterizer;
  RenderResult result;
  std::vector<cv::Mat> images;
  for (int f : kFrames) {
    rasterizer.Forward(frames[f].camera, SplatView::Of(gaussians), options,
                       &result);
    images.push_back(cv::Mat(result.height, result.width, CV_64FC3,
                             result.rgb.data())
                         .clone());
  }
  return images;
}

double LargestDifference(const std::vector<cv::Mat>& a,
                         const std::vector<cv::Mat>& b) {
  double largest = 0;
  for (size_t k = 0; k < a.size(); ++k)
    largest = std::max(largest, cv::norm(a[k], b[k], cv::NORM_INF));
  return largest;
}

TEST(JointStartTest, ZeroFieldsRenderTheStaticModel) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.random_start = true;  // start times must not matter without V
  const GaussianSet stage1 = TrueCanonical();
  MotionField zero_motion(options.motion);
  zero_motion.SetBox({-1, -1, 1}, {1, 1, 4});
  ZeroField(&zero_motion.triplane_params(), &zero_motion.mlp_params());
  JointTrainer trainer(&frames, kTrain, options, stage1, zero_motion);
  ASSERT_GT(trainer.model().num_dynamic(), 0);
  LoopModel start = trainer.model();
  ASSERT_TRUE(start.residual.has_value());
  ZeroField(&start.residual->triplane_params(),
            &start.residual->mlp_params());

  CpuImageRasterizer rasterizer(trainer.render_options());
  const std::vector<cv::Mat> joint =
      RenderCompositions(start, frames, kFrames, &rasterizer);
  const std::vector<cv::Mat> expected =
      StaticRenders(stage1, frames, trainer.render_options());
  EXPECT_LT(LargestDifference(joint, expected), 1e-9);

  // The check sees a hand-over that moves the water: V of one frame's
  // step, or D's own first draw.
  LoopModel moved = start;
  std::fill(moved.motion->mlp_params().end() - 3,
            moved.motion->mlp_params().end(), 0.5);
  EXPECT_GT(LargestDifference(
                RenderCompositions(moved, frames, kFrames, &rasterizer),
                expected),
            1e-3);
  EXPECT_GT(LargestDifference(RenderCompositions(trainer.model(), frames,
                                                 kFrames, &rasterizer),
                              expected),
            1e-9);
}

// With the motion warm-up the trainer's own model at iteration 0 (V
// pretrained and moving, D zeroed) renders Stage 1's model, and V's
// steps grow to their full length by the end of the warm-up.
TEST(JointStartTest, MotionWarmUpStartsFromTheStaticModel) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.random_start = true;
  options.iterations = 20;
  options.motion_warmup = 0.5;
  const GaussianSet stage1 = TrueCanonical();
  MotionField motion(options.motion);
  motion.SetBox({-1, -1, 1}, {1, 1, 4});
  std::fill(motion.mlp_params().end() - 3, motion.mlp_params().end(), 0.5);
  JointTrainer trainer(&frames, kTrain, options, stage1, motion);
  CpuImageRasterizer rasterizer(trainer.render_options());
  const std::vector<cv::Mat> expected =
      StaticRenders(stage1, frames, trainer.render_options());
  LoopModel start = trainer.model();
  ZeroField(&start.residual->triplane_params(),
            &start.residual->mlp_params());
  EXPECT_LT(LargestDifference(
                RenderCompositions(start, frames, kFrames, &rasterizer),
                expected),
            1e-9);
  for (int i = 0; i < 5; ++i) trainer.Step();
  EXPECT_DOUBLE_EQ(trainer.model().motion->displacement_factor(), 0.5);
  for (int i = 0; i < 15; ++i) trainer.Step();
  EXPECT_EQ(trainer.model().motion->displacement_factor(), 1.0);
  EXPECT_EQ(trainer.FinalModel().motion->displacement_factor(), 1.0);
}

TEST(JointStartTest, WaterLossRampRisesOverTheWarmUp) {
  JointTrainerOptions o = TinyOptions();
  EXPECT_EQ(WaterLossRamp(o, 0), 1.0);  // no warm-up: full weight
  o.iterations = 200;
  o.water_loss_warmup = 0.25;
  EXPECT_EQ(WaterLossRamp(o, 0), 0.0);
  EXPECT_DOUBLE_EQ(WaterLossRamp(o, 25), 0.5);
  EXPECT_EQ(WaterLossRamp(o, 50), 1.0);
  EXPECT_EQ(WaterLossRamp(o, 199), 1.0);
}

// At the first step of a warm-up the water losses are measured but weigh
// nothing: the loss is the full-weight trainer's less exactly their
// weighted terms.
TEST(JointStartTest, WarmUpStartsWithoutTheWaterLosses) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions full = TinyOptions();
  full.iterations = 40;
  full.water_energy.motion_weight = 1.0;
  full.water_energy.detail_weight = 2.0;
  full.loop_texture_weight = 3.0;
  JointTrainerOptions warm = full;
  warm.water_loss_warmup = 0.5;
  JointTrainer a(&frames, kTrain, full, TrueCanonical(), std::nullopt);
  JointTrainer b(&frames, kTrain, warm, TrueCanonical(), std::nullopt);
  const JointIterationStats sa = a.Step();
  const JointIterationStats sb = b.Step();
  ASSERT_EQ(sa.frame, sb.frame);
  ASSERT_GE(sa.pair_frame, 0);
  const double water = 1.0 * sa.energy.motion + 2.0 * sa.energy.detail +
                       3.0 * sa.loop_texture;
  ASSERT_GT(water, 1e-6);
  EXPECT_NEAR(sb.loss, sa.loss - water, 1e-9 * sa.loss);
  EXPECT_DOUBLE_EQ(sb.energy.motion, sa.energy.motion);  // still measured
}

}  // namespace
}  // namespace es
