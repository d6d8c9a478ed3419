#include "solvers/train/joint_trainer.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"
#include "core/loop/frame_composer.h"
#include "core/loop/loop_renderer.h"
#include "core/render/rasterizer.h"
#include "costs/water_texture_loss.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/train/joint_training_steps.h"
#include "tests/tiny_loop_scene.h"
#include "tests/expect_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;
using namespace tiny_loop;  // NOLINT: the scene's constants

const std::vector<int> kTrain = {0, 1, 2, 4, 5, 7, 8, 9, 10};
const std::vector<int> kTest = {3, 6, 11};

TEST(JointTrainerTest, LearnsALoopingTranslation) {
  const std::vector<Frame> frames = TrueFrames();
  const JointTrainerOptions options = TinyOptions();
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  EXPECT_EQ(trainer.model().dynamic_index,
            (std::vector<int>{6, 7, 8, 9}));
  const LoopMetrics before = EvaluateLoopModel(
      trainer.model(), frames, kTest, trainer.render_options());
  auto mean_loss = [&trainer](int steps) {
    double sum = 0;
    for (int s = 0; s < steps; ++s) sum += trainer.Step().loss;
    return sum / steps;
  };
  const double first = mean_loss(18);
  mean_loss(options.iterations - 36);
  const double last = mean_loss(18);
  EXPECT_LT(last, 0.5 * first) << "first " << first << " last " << last;
  const LoopMetrics after = EvaluateLoopModel(
      trainer.model(), frames, kTest, trainer.render_options());
  EXPECT_EQ(after.frames, 3);
  EXPECT_TRUE(std::isfinite(after.psnr) && std::isfinite(after.ssim));
  EXPECT_GT(after.psnr, before.psnr + 10) << "before " << before.psnr;
  // V recovers the true velocity at the dynamic Gaussians.
  const LoopModel& m = trainer.model();
  std::vector<double> x0, v(3 * kNumDynamic);
  for (int n : m.dynamic_index)
    for (int j = 0; j < 3; ++j) x0.push_back(m.gaussians.means[3 * n + j]);
  FieldWorkspace ws;
  m.motion->Evaluate(m.motion->params(), kNumDynamic, x0.data(), v.data(),
                     &ws);
  Eigen::Vector3d mean_v = Eigen::Vector3d::Zero();
  for (int k = 0; k < kNumDynamic; ++k) mean_v += Eigen::Vector3d(&v[3 * k]);
  mean_v /= kNumDynamic;
  EXPECT_LT((mean_v - kVelocity).norm(), 0.2 * kVelocity.norm())
      << mean_v.transpose();

  // Frames COLMAP did not register leave gaps: a frame is still composed
  // at its place in the video, not at its rank among the frames kept.
  std::vector<Frame> registered = frames;
  registered.erase(registered.begin() + 5);
  registered.erase(registered.begin() + 2);  // times 0 1 3 4 6 7 ...
  for (int time : {6, 7}) {
    const int index = time - 2;
    ASSERT_EQ(registered[index].time_index, time);
    const LoopMetrics full = EvaluateLoopModel(m, frames, {time},
                                               trainer.render_options());
    const LoopMetrics gap = EvaluateLoopModel(m, registered, {index},
                                              trainer.render_options());
    EXPECT_EQ(gap.psnr, full.psnr) << "time " << time;
    EXPECT_GT(full.psnr, 25) << "time " << time;
  }
}

void ExpectSameModel(const LoopModel& a, const LoopModel& b) {
  EXPECT_EQ(a.dynamic_index, b.dynamic_index);
  EXPECT_EQ(a.start_times, b.start_times);
  EXPECT_EQ(a.gaussians.means, b.gaussians.means);
  EXPECT_EQ(a.gaussians.opacity_logits, b.gaussians.opacity_logits);
  EXPECT_EQ(a.gaussians.sh, b.gaussians.sh);
  const FieldParams pa = a.motion->params(), pb = b.motion->params();
  for (int i = 0; i < a.motion->mlp().num_params(); ++i)
    ASSERT_EQ(pa.mlp[i], pb.mlp[i]) << i;
  const FieldParams ra = a.residual->params(), rb = b.residual->params();
  for (int i = 0; i < a.residual->triplane().num_params(); ++i)
    ASSERT_EQ(ra.triplane[i], rb.triplane[i]) << i;
}

// Mean of V at the dynamic Gaussians' canonical positions.
Eigen::Vector3d MeanVelocity(const LoopModel& m) {
  std::vector<double> x, v(3 * m.num_dynamic());
  for (int n : m.dynamic_index)
    for (int j = 0; j < 3; ++j) x.push_back(m.gaussians.means[3 * n + j]);
  FieldWorkspace ws;
  m.motion->Evaluate(m.motion->params(), m.num_dynamic(), x.data(), v.data(),
                     &ws);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int k = 0; k < m.num_dynamic(); ++k) mean += Eigen::Vector3d(&v[3 * k]);
  return mean / m.num_dynamic();
}

// Samples that say the water moves the other way than the images show: a
// strong prior holds V there, without it V follows the images.
TEST(JointTrainerTest, SceneFlowPriorPullsVToTheSamples) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.iterations = 50;
  const Eigen::Vector3d other(-0.06, 0.0, 0.03);
  auto train = [&](double weight) {
    options.flow_prior.weight = weight;
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    trainer.SetSceneFlowPrior(FlowSamples(other));
    double prior = 0;
    while (trainer.iteration() < options.iterations)
      prior += trainer.Step().flow_prior;
    EXPECT_EQ(prior > 0, weight > 0);
    return MeanVelocity(trainer.model());
  };
  const Eigen::Vector3d free = train(0), held = train(100);
  EXPECT_LT((held - other).norm(), 0.3 * other.norm()) << held.transpose();
  EXPECT_LT((free - kVelocity).norm(), (free - other).norm())
      << free.transpose();
}

TEST(JointTrainerTest, ResumeGivesTheUninterruptedResult) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.random_start = true;
  options.mask_weight = 0.5;  // dynamic logits learn: refreshes change sets
  options.iterations = 30;
  options.flow_prior.weight = 0.5;  // its batches must not depend on a run
  options.flow_prior.batch_size = 16;
  options.water_energy.motion_weight = 0.5;  // frame pairs
  options.water_energy.detail_weight = 0.5;
  options.water_texture.weight = 0.5;  // its directions must follow the step
  const std::vector<SceneFlowSample> samples = FlowSamples(kVelocity);
  JointTrainer straight(&frames, kTrain, options, TrueCanonical(),
                        std::nullopt);
  straight.SetSceneFlowPrior(samples);
  for (int i = 0; i < 30; ++i) straight.Step();

  const std::string path =
      (fs::path(::testing::TempDir()) /
       ("es_joint_ckpt_" + std::to_string(getpid()) + ".bin"))
          .string();
  {
    JointTrainer first(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
    first.SetSceneFlowPrior(samples);
    for (int i = 0; i < 20; ++i) first.Step();  // a refresh comes next
    WriteJointCheckpoint(first.Save(), path);
  }
  JointTrainer resumed(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  resumed.SetSceneFlowPrior(samples);
  resumed.Restore(ReadJointCheckpoint(path), path);
  EXPECT_EQ(resumed.iteration(), 20);
  while (resumed.iteration() < 30) resumed.Step();
  fs::remove(path);
  ExpectSameModel(straight.model(), resumed.model());
}

// With the energy term each step also renders the sampled frame's
// neighbour among the training frames (the next, else the previous), and
// the term moves the model: trained with it, the frame-to-frame change of
// the water is closer to the input's than trained with a negligible
// weight (which measures the term without following it).
TEST(JointTrainerTest, EnergyTermPairsNeighboursAndMovesTheWater) {
  const std::vector<Frame> frames = TrueFrames();
  const std::vector<int> expected = {1, 2, 1, -1, 5, 4, -1, 8, 9, 10, 9};
  auto train = [&](double weight) {
    JointTrainerOptions options = TinyOptions();
    options.iterations = 90;
    options.water_energy.motion_weight = weight;
    options.water_energy.detail_weight = 0.0;
    options.use_motion = false;  // D alone must make the change
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    double last = 0;
    for (int i = 0; i < options.iterations; ++i) {
      const JointIterationStats s = trainer.Step();
      EXPECT_EQ(s.pair_frame, expected.at(s.frame)) << "frame " << s.frame;
      if (i >= options.iterations - 18) last += s.energy.motion;
    }
    return last;
  };
  const double followed = train(1.0), measured = train(1e-9);
  EXPECT_GT(measured, 0);
  EXPECT_LT(followed, 0.8 * measured) << followed << " vs " << measured;
}

// The texture term alone also trains on frame pairs, and following it
// brings the rendered water's texture distribution closer to the input's
// than a negligible weight does.
TEST(JointTrainerTest, TextureTermPairsNeighboursAndMatchesTheTexture) {
  const std::vector<Frame> frames = TrueFrames();
  auto train = [&](double weight) {
    JointTrainerOptions options = TinyOptions();
    options.iterations = 90;
    options.water_texture.weight = weight;
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    double last = 0;
    for (int i = 0; i < options.iterations; ++i) {
      const JointIterationStats s = trainer.Step();
      EXPECT_GE(s.pair_frame, 0) << "frame " << s.frame;
      EXPECT_EQ(s.energy.motion, 0.0);
      if (i >= options.iterations - 18) last += s.texture;
    }
    return last;
  };
  const double followed = train(30.0), measured = train(1e-9);
  EXPECT_GT(measured, 0);
  EXPECT_LT(followed, 0.8 * measured) << followed << " vs " << measured;
}

// The unweighted texture distance of `frame` composed with every water
// Gaussian at `cycle_number` (nullopt: the frame's own) against the input
// frame, with the loop term's directions of `iteration`.
double LoopTextureDistance(const LoopModel& model, const Frame& frame,
                           WaterTextureOptions options, int64_t iteration,
                           const RenderOptions& render_options,
                           std::optional<int> cycle_number = 0) {
  FrameComposer composer;
  Rasterizer rasterizer;
  RenderResult render;
  rasterizer.Forward(frame.camera,
                     composer.Compose(LoopModelView::Of(model),
                                      frame.time_index, cycle_number),
                     render_options, &render);
  options.weight = 1;
  WaterTextureLoss loss(options);
  return loss.Evaluate(render.rgb.data(), frame.image, frame.mask, 1.0,
                       LoopTextureDraw(iteration), nullptr);
}

// With loop_texture_weight each step also scores its frame as the loop
// plays it: composed with every water Gaussian at cycle number 0, rendered
// and compared with the input frame; here recomputed from the model before
// each step. With random start times the video's own composition of a
// later frame differs, and so does its texture distance.
TEST(JointTrainerTest, LoopTextureScoresTheFrameAsTheLoopPlaysIt) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.iterations = 8;
  options.random_start = true;
  options.loop_texture_weight = 0.5;
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  double largest_gap = 0;
  for (int i = 0; i < options.iterations; ++i) {
    const LoopModel before = trainer.model();
    const JointIterationStats s = trainer.Step();
    EXPECT_EQ(s.pair_frame, -1);  // no pair term is on
    const Frame& frame = frames[s.frame];
    const WaterTextureOptions& texture = options.water_texture;
    EXPECT_NEAR(s.loop_texture,
                LoopTextureDistance(before, frame, texture, i,
                                    trainer.render_options()),
                1e-9)
        << "step " << i;
    largest_gap = std::max(
        largest_gap,
        std::abs(s.loop_texture -
                 LoopTextureDistance(before, frame, texture, i,
                                     trainer.render_options(), std::nullopt)));
  }
  EXPECT_GT(largest_gap, 1e-6);
}

// A small step that follows the loop texture term lowers the loop's
// texture distance at that step's frame and directions more than the same
// step with a negligible weight does (a wrong sign or a gradient that
// never arrives would not). Over many steps the new directions each step
// draws keep the distance at a noise floor that this tiny scene's
// photometric fit already nearly reaches, so a long run would not tell.
TEST(JointTrainerTest, LoopTextureStepLowersTheLoopsTextureDistance) {
  const std::vector<Frame> frames = TrueFrames();
  for (uint64_t seed : {1, 2, 3}) {
    auto after_one_step = [&](double weight) {
      JointTrainerOptions options = TinyOptions();
      options.random_start = true;
      options.seed = seed;
      options.loop_texture_weight = weight;
      // Small steps: Adam's first step moves every parameter by its rate.
      const double k = 1e-2;
      SplatLearningRateOptions& r = options.splat_lr;
      for (double* lr : {&r.means_initial, &r.means_final, &r.log_scales,
                         &r.quats, &r.opacity, &r.sh_dc, &r.sh_rest,
                         &options.lr_motion_triplane, &options.lr_motion_mlp,
                         &options.lr_residual_triplane,
                         &options.lr_residual_mlp})
        *lr *= k;
      JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                           std::nullopt);
      const JointIterationStats s = trainer.Step();
      return LoopTextureDistance(trainer.model(), frames[s.frame],
                                 options.water_texture, 0,
                                 trainer.render_options()) /
             s.loop_texture;  // the distance after over before
    };
    const double followed = after_one_step(100), ignored = after_one_step(1e-9);
    EXPECT_LT(followed, 1.0) << "seed " << seed;
    EXPECT_GT(1 - followed, 1.05 * (1 - ignored))
        << followed << " vs " << ignored << ", seed " << seed;
  }
}

TEST(JointTrainerTest, WaterDensificationGrowsWithinBudgetAndResumes) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.random_start = true;
  options.iterations = 60;  // densifies at 10, 20, 30
  options.water_densify.interval = 10;
  options.water_densify.fraction = 0.5;
  options.water_densify.max_growth = 2.25;  // 4 -> 9 water Gaussians
  options.water_densify.views = 4;
  options.water_densify.split_pixels = 0.5;
  JointTrainer straight(&frames, kTrain, options, TrueCanonical(),
                        std::nullopt);
  int added = 0;
  for (int i = 0; i < 60; ++i) {
    const JointIterationStats s = straight.Step();
    added += s.densified.cloned + s.densified.split;
    EXPECT_LE(straight.model().num_dynamic(), 9);
  }
  EXPECT_EQ(straight.model().num_dynamic(), 9);
  EXPECT_EQ(added, 5);  // one Gaussian more per split or clone
  EXPECT_EQ(straight.model().gaussians.size(), kNumStatic + 9);
  EXPECT_TRUE(AllFinite(straight.model().gaussians));

  const std::string path =
      (fs::path(::testing::TempDir()) /
       ("es_joint_densify_" + std::to_string(getpid()) + ".bin"))
          .string();
  {
    JointTrainer first(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
    for (int i = 0; i < 15; ++i) first.Step();
    WriteJointCheckpoint(first.Save(), path);
  }
  JointTrainer resumed(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  resumed.Restore(ReadJointCheckpoint(path), path);
  while (resumed.iteration() < 60) resumed.Step();
  fs::remove(path);
  ExpectSameModel(straight.model(), resumed.model());
}

TEST(JointTrainerTest, RefreshKeepsStartTimesOfGaussiansThatStay) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.random_start = true;
  options.refresh_interval = 10;
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  const std::vector<int> times = trainer.model().start_times;
  for (int t : times) EXPECT_TRUE(t >= 0 && t < kCycle);
  JointCheckpoint c = trainer.Save();
  c.iteration = 10;  // the next Step refreshes
  c.gaussians.dynamic_logits[6] = -4;  // leaves the water
  c.gaussians.dynamic_logits[2] = 4;   // joins it
  trainer.Restore(c, "test");
  trainer.Step();
  const LoopModel& m = trainer.model();
  ASSERT_EQ(m.dynamic_index, (std::vector<int>{2, 7, 8, 9}));
  EXPECT_EQ(m.start_times[1], times[1]);
  EXPECT_EQ(m.start_times[2], times[2]);
  EXPECT_EQ(m.start_times[3], times[3]);
  EXPECT_TRUE(m.start_times[0] >= 0 && m.start_times[0] < kCycle);
}

TEST(JointTrainerTest, AblationsTrainAndStayFinite) {
  const std::vector<Frame> frames = TrueFrames();
  for (int variant = 0; variant < 3; ++variant) {
    JointTrainerOptions options = TinyOptions();
    options.use_motion = variant != 0;
    options.use_residual = variant != 1;
    if (variant == 2) options.use_motion = options.use_residual = false;
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    EXPECT_EQ(trainer.model().motion.has_value(), options.use_motion);
    EXPECT_EQ(trainer.model().residual.has_value(), options.use_residual);
    for (int i = 0; i < 5; ++i)
      EXPECT_TRUE(std::isfinite(trainer.Step().loss)) << variant;
    const LoopMetrics m = EvaluateLoopModel(trainer.model(), frames, kTest,
                                            trainer.render_options());
    EXPECT_TRUE(std::isfinite(m.psnr)) << variant;
  }
}

// Every frame of a looping model composed at its own index (Alg. 1), and
// the loop as the animation plays it (Alg. 2, p = 0), rendered at a camera.
std::vector<std::vector<double>> RenderAllFrames(const LoopModel& model) {
  std::vector<std::vector<double>> images;
  Rasterizer rasterizer;
  RenderResult render;
  FrameComposer composer;
  for (int i = 0; i < kFrames; ++i) {
    rasterizer.Forward(TinyCamera(i),
                       composer.Compose(LoopModelView::Of(model), i),
                       RenderOptions(), &render);
    images.push_back(render.rgb);
  }
  LoopRenderer player(&model, RenderOptions());
  player.Start(0);
  for (int i = 0; i < kCycle; ++i, player.Advance())
    images.push_back(player.Render(TinyCamera(i)).rgb);
  return images;
}

TEST(JointTrainerTest, FinalModelDropsOnlyWhatNoFrameShows) {
  const std::vector<Frame> frames = TrueFrames();
  GaussianSet canonical = TrueCanonical();
  canonical.opacity_logits[1] = -8;  // static, invisible
  canonical.opacity_logits[7] = -9;  // dynamic, invisible in every frame
  canonical.opacity_logits[8] = -6;  // dynamic, visible where D lifts it
  for (int variant = 0; variant < 2; ++variant) {
    JointTrainerOptions options = TinyOptions();
    options.use_residual = variant == 1;
    JointTrainer trainer(&frames, kTrain, options, canonical, std::nullopt);
    LoopModel model = trainer.model();
    if (model.residual) {
      // Large opacity offsets that change with the cycle index.
      for (double& w : model.residual->mlp_params()) w *= 40;
    }
    LoopModel pruned = model;
    const int removed = PruneInvisible(kFrames, &pruned);
    if (variant == 0) {
      EXPECT_EQ(removed, 3);
      EXPECT_EQ(pruned.dynamic_index, (std::vector<int>{5, 6}));
      int final_removed = -1;
      EXPECT_EQ(trainer.FinalModel(&final_removed).gaussians.size(),
                pruned.gaussians.size());
      EXPECT_EQ(final_removed, 3);
    } else {
      // The static one goes; D lifts at least one dynamic one into view.
      EXPECT_GE(removed, 1);
      EXPECT_LT(removed, 3);
    }
    EXPECT_EQ(pruned.gaussians.size(), model.gaussians.size() - removed);
    EXPECT_EQ(pruned.num_dynamic(),
              static_cast<int>(pruned.start_times.size()));
    const auto before = RenderAllFrames(model), after = RenderAllFrames(pruned);
    for (size_t f = 0; f < before.size(); ++f)
      for (size_t p = 0; p < before[f].size(); ++p)
        ASSERT_NEAR(before[f][p], after[f][p], 1e-6) << variant << " " << f;
  }
}

// A frame with a NaN pixel: its steps are skipped and counted, the model
// and fields stay finite; a NaN learning rate stops at the first update.
TEST(JointTrainerTest, NonFiniteStepsAreSkippedAndDivergenceStops) {
  std::vector<Frame> frames = TrueFrames();
  frames[kTrain[4]].image.at<cv::Vec3f>(3, 3)[0] = NAN;
  JointTrainerOptions options = TinyOptions();
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  int skipped = 0;
  for (int i = 0; i < 18; ++i) skipped += trainer.Step().skipped;
  EXPECT_EQ(skipped, 2);  // two epochs of nine frames
  EXPECT_EQ(trainer.skipped_steps(), 2);
  EXPECT_TRUE(AllFinite(trainer.model().gaussians));
  const MotionField& v = *trainer.model().motion;
  const ResidualField& d = *trainer.model().residual;
  EXPECT_TRUE(AllFinite(v.params().triplane, v.triplane().num_params()));
  EXPECT_TRUE(AllFinite(d.params().mlp, d.mlp().num_params()));

  const std::vector<Frame> good = TrueFrames();
  options.lr_motion_mlp = NAN;
  JointTrainer diverging(&good, kTrain, options, TrueCanonical(),
                         std::nullopt);
  EXPECT_THROW(diverging.Step(), TrainingDiverged);
}

// D (issue 46): es_train --lr_means 1e30 trained to finite garbage
// (held-out PSNR 5.6 dB against 19.3) and exited 0; a runaway splat or
// field block now stops the first step, naming the flag to lower.
TEST(JointTrainerTest, RunawayLearningRateStopsTheRunNamingIt) {
  const std::vector<Frame> frames = TrueFrames();
  for (const char* flag : {"--lr_means", "--lr_motion_mlp"}) {
    JointTrainerOptions options = TinyOptions();
    if (std::string(flag) == "--lr_means")
      options.splat_lr.means_initial = options.splat_lr.means_final = 1e30;
    else
      options.lr_motion_mlp = 1e30;
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    ExpectErrorNaming<TrainingDiverged>([&] { trainer.Step(); },
                                        {std::string(flag) + " 1e+30"});
  }
}

// ... and leaves a normal run far alone: every block, splats and fields,
// ends more than a thousand times below its bound.
TEST(JointTrainerTest, NormalRunStaysFarFromTheRunawayBounds) {
  const std::vector<Frame> frames = TrueFrames();
  const JointTrainerOptions options = TinyOptions();
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  const std::vector<GuardedBlock> blocks = GuardedJointBlocks(
      options, trainer.model(), CameraExtent(frames, kTrain));
  for (int i = 0; i < options.iterations; ++i) trainer.Step();
  LoopModel model = trainer.model();
  std::vector<double> magnitudes = SplatMagnitudes(model.gaussians);
  for (const std::vector<double>* block : FieldParamBlocks(&model))
    magnitudes.push_back(MaxMagnitude(*block));
  ASSERT_EQ(blocks.size(), magnitudes.size());
  for (size_t b = 0; b < blocks.size(); ++b)
    EXPECT_LT(magnitudes[b], 1e-3 * blocks[b].bound) << blocks[b].name;
}

TEST(JointTrainerTest, MismatchedCheckpointIsAnInputError) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  JointTrainer full(&frames, kTrain, options, TrueCanonical(), std::nullopt);
  options.use_residual = false;
  JointTrainer no_residual(&frames, kTrain, options, TrueCanonical(),
                           std::nullopt);
  EXPECT_THROW(no_residual.Restore(full.Save(), "ckpt"), InputError);
}

TEST(JointTrainerTest, ResidualCycleNumbersCoverTheWholeVideo) {
  // Frame i has cycle number p = floor((i - t0) / L) in [-1, (N-1) / L].
  EXPECT_EQ(CyclesCovering(12, 4), 4);
  EXPECT_EQ(CyclesCovering(1000, 15), 68);
  for (int frames : {2, 15, 16, 99, 481}) {
    const int m = CyclesCovering(frames, 15);
    EXPECT_GT(m, (frames - 1) / 15) << frames;  // the largest p
    EXPECT_GT(m, 1) << frames;                  // p = -1
  }
  const std::vector<Frame> frames = TrueFrames();
  JointTrainer trainer(&frames, kTrain, TinyOptions(), TrueCanonical(),
                       std::nullopt);
  EXPECT_EQ(trainer.model().residual->options().max_cycles,
            CyclesCovering(kFrames, kCycle));
}

TEST(JointTrainerTest, MaxDynamicPixelsKeepsWaterGaussiansSmall) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.max_dynamic_pixels = 0.5;  // the true ones are ~0.9 px
  options.iterations = 10;
  JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                       std::nullopt);
  for (int i = 0; i < 10; ++i) trainer.Step();
  const GaussianSet& g = trainer.model().gaussians;
  for (int n : trainer.model().dynamic_index) {
    // Distance ~2-2.3 from cameras with fx 30.
    const double z = Eigen::Vector3d(&g.means[3 * n]).norm();
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(std::exp(g.log_scales[3 * n + a]), 0.5 * z / 30 * 1.05);
    }
  }
  // Static Gaussians are not limited.
  EXPECT_GT(std::exp(g.log_scales[0]), 0.1);
}

// The trainer's Euler options reach the chain of its loss: a tiny step
// limit clamps the steps that the default one leaves alone.
TEST(JointTrainerTest, EulerOptionsReachTheChain) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.iterations = 4;
  for (const double fraction : {0.25, 1e-6}) {
    options.euler.max_step_fraction = fraction;
    JointTrainer trainer(&frames, kTrain, options, TrueCanonical(),
                         std::nullopt);
    int64_t clamped = 0, evaluations = 0;
    for (int i = 0; i < options.iterations; ++i) {
      const JointIterationStats stats = trainer.Step();
      clamped += stats.euler.clamped_steps;
      evaluations += stats.euler.velocity_evaluations;
    }
    ASSERT_GT(evaluations, 0);
    if (fraction > 0.1) {
      EXPECT_EQ(clamped, 0);
    } else {
      EXPECT_GT(clamped, 0);
    }
  }
}

// An empty field box in a corrupt checkpoint used to reach
// Triplane::SetBox's CHECK on resume; the reader rejects it.
TEST(JointTrainerTest, CheckpointWithAnEmptyFieldBoxIsAnInputError) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainer trainer(&frames, kTrain, TinyOptions(), TrueCanonical(),
                       std::nullopt);
  const std::string path = ::testing::TempDir() + "/empty_box_" +
                           std::to_string(::getpid()) + ".ckpt";
  JointCheckpoint c = trainer.Save();
  WriteJointCheckpoint(c, path);
  EXPECT_NO_THROW(ReadJointCheckpoint(path));
  c.field_boxes[3] = c.field_boxes[0];  // V's box: max x == min x
  WriteJointCheckpoint(c, path);
  EXPECT_THROW(ReadJointCheckpoint(path), InputError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace es
