#include "solvers/train/static_trainer.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <set>

#include "core/base/input_error.h"
#include "core/model/gaussian_init.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/eval/static_eval.h"
#include "solvers/optim/frame_sampler.h"
#include "tests/centered_camera.h"
#include "tests/expect_same_gaussians.h"
#include "tests/memory_limit.h"
#include "tests/slab_scene.h"
#include "tests/expect_error.h"

namespace es {
namespace {

constexpr int kWidth = 64, kHeight = 48;

Camera LookAt(const Eigen::Vector3d& center) {
  return LookingAtOrigin(CenteredCamera(kWidth, kHeight, 60), center);
}

// A slab of ~300 opaque Gaussians seen from 10 cameras on an arc; the
// Gaussians with x > 0 are "water" and render the mask.
struct SyntheticScene {
  GaussianSet truth;
  std::vector<Frame> frames;
  std::vector<int> train, test;
  std::vector<Eigen::Vector3d> points, colors;

  SyntheticScene() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> noise(0, 1);
    truth.Resize(300);
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector3d color = DrawSlabGaussian(0.12, i, &rng, &truth);
      points.emplace_back(
          Eigen::Vector3d::Map(&truth.means[3 * i]) +
          0.03 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
      colors.push_back(color);
    }
    std::vector<double> water;
    const SplatView view = WaterMarkedView(truth, &water);
    Rasterizer rasterizer;
    RenderResult render;
    for (int k = 0; k < 10; ++k) {
      const double angle = -0.5 + k * 0.11;
      Frame f = RenderedFrame(
          LookAt(4.0 * Eigen::Vector3d(std::sin(angle), 0.15 * u(rng),
                                       -std::cos(angle))),
          view, &rasterizer, &render);
      cv::threshold(f.mask, f.mask, 0.5, 1.0, cv::THRESH_BINARY);
      frames.push_back(f);
      (k == 3 || k == 7 ? test : train).push_back(k);
    }
  }
};

StaticTrainerOptions FastOptions(int iterations) {
  StaticTrainerOptions o;
  o.iterations = iterations;
  o.max_sh_degree = 1;
  o.sh_degree_interval = 500;
  o.densify_options.from_iteration = 100;
  o.densify_options.until_iteration = iterations / 2;
  o.densify_options.interval = 100;
  o.densify_options.opacity_reset_interval = 100000;
  o.densify_options.max_gaussians = 1000;  // keeps the test fast
  return o;
}

TEST(StaticTrainerTest, FitsASyntheticSceneAndItsMask) {
  const SyntheticScene scene;
  StaticTrainer trainer(&scene.frames, scene.train, FastOptions(1000),
                        InitGaussiansFromPoints(scene.points, scene.colors, 0));
  ASSERT_TRUE(trainer.uses_masks());
  const StaticMetrics before = EvaluateStatic(
      trainer.gaussians(), scene.frames, scene.test, trainer.render_options());
  double first_loss = 0, last_loss = 0;
  for (int i = 0; i < 1000; ++i) {
    const IterationStats s = trainer.Step();
    ASSERT_TRUE(std::isfinite(s.loss));
    if (i < 50) first_loss += s.loss;
    if (i >= 950) last_loss += s.loss;
  }
  EXPECT_LT(last_loss, 0.2 * first_loss);
  const StaticMetrics after = EvaluateStatic(
      trainer.gaussians(), scene.frames, scene.test, trainer.render_options());
  std::printf(
      "held-out PSNR %.2f -> %.2f dB, SSIM %.3f, water PSNR %.2f, "
      "mask P/R %.3f/%.3f, %d Gaussians\n",
      before.psnr, after.psnr, after.ssim, after.psnr_water,
      after.mask_precision, after.mask_recall, trainer.gaussians().size());
  EXPECT_GT(after.psnr, 30.0);
  EXPECT_GT(after.ssim, 0.95);
  EXPECT_GT(after.mask_precision, 0.9);
  EXPECT_GT(after.mask_recall, 0.9);
}

TEST(StaticTrainerTest, ResumeFromCheckpointIsBitExact) {
  // One thread: the rasterizer's parallel gradient sums are order-dependent.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const SyntheticScene scene;
  StaticTrainerOptions o = FastOptions(300);
  o.sh_degree_interval = 100;
  o.densify_options.from_iteration = 50;
  o.densify_options.interval = 50;
  // Densification stops at half of the run (150); the checkpoint at 120
  // falls between densify steps, so the restored statistics feed the one at
  // 150, and the opacity reset at 100 is before it.
  o.densify_options.until_iteration = 250;
  o.densify_options.opacity_reset_interval = 100;
  o.densify_options.max_gaussians = 500;
  const GaussianSet init =
      InitGaussiansFromPoints(scene.points, scene.colors, 0);

  StaticTrainer full(&scene.frames, scene.train, o, init);
  for (int i = 0; i < 300; ++i) full.Step();

  const std::string path =
      std::string(ES_BINARY_DIR) + "/static_trainer_test.ckpt";
  {
    StaticTrainer first(&scene.frames, scene.train, o, init);
    for (int i = 0; i < 120; ++i) first.Step();
    WriteCheckpoint(first.Save(), path);
  }  // "killed"
  StaticTrainer resumed(&scene.frames, scene.train, o, init);
  resumed.Restore(ReadCheckpoint(path));
  EXPECT_EQ(resumed.iteration(), 120);
  for (int i = 0; i < 180; ++i) resumed.Step();
  omp_set_num_threads(threads);
  std::remove(path.c_str());

  const GaussianSet& a = full.gaussians();
  const GaussianSet& b = resumed.gaussians();
  EXPECT_NE(a.size(), init.size());  // densification happened
  EXPECT_EQ(a.sh_degree, 2 > o.max_sh_degree ? o.max_sh_degree : 2);
  ExpectSameGaussians(a, b);
}

double MaxOpacity(const GaussianSet& g) {
  double m = 0;
  for (double logit : g.opacity_logits) m = std::max(m, Sigmoid(logit));
  return m;
}

TEST(StaticTrainerTest, ResetsOpacityOnlyInTheFirstHalfOfTheRun) {
  const SyntheticScene scene;
  StaticTrainerOptions o = FastOptions(200);
  o.densify_options.from_iteration = 1000;  // resets only, no clone/split
  o.densify_options.until_iteration = 1000;
  o.densify_options.opacity_reset_interval = 100;
  StaticTrainer trainer(&scene.frames, scene.train, o,
                        InitGaussiansFromPoints(scene.points, scene.colors, 0));
  for (int i = 0; i < 100; ++i) trainer.Step();
  // Iteration 100 is still in the first half: it resets.
  EXPECT_LE(MaxOpacity(trainer.gaussians()), 0.01 + 1e-12);
  for (int i = 0; i < 100; ++i) trainer.Step();
  // Densification (and with it the reset) stops at half of the run, so the
  // last iteration does not leave the model transparent.
  EXPECT_GT(MaxOpacity(trainer.gaussians()), 0.05);
}

// A frame that yields a NaN loss (here one NaN pixel) skips its steps, which
// are counted; the other frames train on and the model stays finite.
TEST(StaticTrainerTest, NonFiniteStepsAreSkippedAndCounted) {
  SyntheticScene scene;
  scene.frames[scene.train[2]].image.at<cv::Vec3f>(5, 7)[1] = NAN;
  StaticTrainer trainer(&scene.frames, scene.train, FastOptions(40),
                        InitGaussiansFromPoints(scene.points, scene.colors, 0));
  int skipped = 0;
  for (int i = 0; i < 40; ++i) skipped += trainer.Step().skipped;
  // Eight training frames, shuffled per epoch: the bad one comes up once in
  // each of the five epochs.
  EXPECT_EQ(skipped, 5);
  EXPECT_EQ(trainer.skipped_steps(), 5);
  EXPECT_EQ(trainer.iteration(), 40);
  EXPECT_TRUE(AllFinite(trainer.gaussians()));
}

// A state that only produces non-finite steps stops the run after
// max_nonfinite_steps of them, and skipped steps never touch the model.
TEST(StaticTrainerTest, TooManyNonFiniteStepsInARowStopTheRun) {
  SyntheticScene scene;
  for (int k : scene.train) scene.frames[k].image.at<cv::Vec3f>(0, 0)[2] = NAN;
  const GaussianSet initial =
      InitGaussiansFromPoints(scene.points, scene.colors, 0);
  StaticTrainerOptions options = FastOptions(100);
  options.max_nonfinite_steps = 4;
  StaticTrainer trainer(&scene.frames, scene.train, options, initial);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(trainer.Step().skipped);
  EXPECT_FALSE(trainer.last_step_ok());
  EXPECT_THROW(trainer.Step(), TrainingDiverged);
  EXPECT_EQ(trainer.gaussians().means, initial.means);
  EXPECT_EQ(trainer.gaussians().log_scales, initial.log_scales);
  EXPECT_EQ(trainer.gaussians().sh, initial.sh);
}

// A learning rate that makes the parameters non-finite (D2: --lr_opacity
// nan) stops at the first update instead of training on to write NaNs.
TEST(StaticTrainerTest, NonFiniteParametersStopTheRunAtOnce) {
  const SyntheticScene scene;
  StaticTrainerOptions options = FastOptions(100);
  options.splat_lr.opacity = NAN;
  StaticTrainer trainer(&scene.frames, scene.train, options,
                        InitGaussiansFromPoints(scene.points, scene.colors, 0));
  EXPECT_THROW(trainer.Step(), TrainingDiverged);
}

// D (issue 46): es_static --lr_position 1e30 or --lr_scale 1e30 trained to
// finite garbage (held-out PSNR 5.6 dB) and exited 0; the first step now
// stops the run, naming the flag to lower.
TEST(StaticTrainerTest, RunawayLearningRateStopsTheRunNamingIt) {
  const SyntheticScene scene;
  for (const char* flag : {"--lr_position", "--lr_scale"}) {
    StaticTrainerOptions options = FastOptions(100);
    if (std::string(flag) == "--lr_position")
      options.splat_lr.means_initial = options.splat_lr.means_final = 1e30;
    else
      options.splat_lr.log_scales = 1e30;
    StaticTrainer trainer(&scene.frames, scene.train, options,
                          InitGaussiansFromPoints(scene.points, scene.colors, 0));
    ExpectErrorNaming<TrainingDiverged>([&] { trainer.Step(); },
                                        {std::string(flag) + " 1e+30"});
  }
}

// The rule leaves a normal run far alone: after a full short run with
// densification, every block is more than a thousand times below its
// bound.
TEST(StaticTrainerTest, NormalRunStaysFarFromTheRunawayBounds) {
  const SyntheticScene scene;
  const StaticTrainerOptions options = FastOptions(400);
  const GaussianSet initial =
      InitGaussiansFromPoints(scene.points, scene.colors, 0);
  StaticTrainer trainer(&scene.frames, scene.train, options, initial);
  for (int i = 0; i < options.iterations; ++i) trainer.Step();
  const std::vector<GuardedBlock> blocks =
      GuardedSplatBlocks(initial, trainer.scene_extent(), options.splat_lr,
                         options.lr_flags);
  const std::vector<double> magnitudes =
      SplatMagnitudes(trainer.gaussians());
  ASSERT_EQ(blocks.size(), magnitudes.size());
  for (size_t b = 0; b < blocks.size(); ++b)
    EXPECT_LT(magnitudes[b], 1e-3 * blocks[b].bound) << blocks[b].name;
}

TEST(CheckpointTest, BadFilesAreInputErrors) {
  const std::string path = std::string(ES_BINARY_DIR) + "/checkpoint_test.ckpt";
  EXPECT_THROW(ReadCheckpoint(path + ".missing"), InputError);
  Checkpoint c;
  c.gaussians.Resize(3);
  c.adam.m = c.adam.v = c.gaussians;
  c.grad_sum = c.grad_count = c.max_radius = {0, 0, 0};
  c.iteration = 42;
  WriteCheckpoint(c, path);
  EXPECT_EQ(ReadCheckpoint(path).iteration, 42);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)),
                    std::istreambuf_iterator<char>());
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), bytes.size() / 2);
  EXPECT_THROW(ReadCheckpoint(path), InputError);
  std::remove(path.c_str());
}

// D8 (fuzzer): a 28-byte file whose first array claims 2^37 values used to
// allocate gigabytes before reporting "truncated"; lengths are now checked
// against the bytes left.
TEST(CheckpointTest, HugeArrayLengthIsRejectedBeforeAllocating) {
  const std::string path =
      std::string(ES_BINARY_DIR) + "/checkpoint_huge_test.ckpt";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write("ESCKPT02", 8);
    const int64_t iteration = 1;
    const int32_t sh_degree = 0;
    const uint64_t length = uint64_t{1} << 37;
    out.write(reinterpret_cast<const char*>(&iteration), 8);
    out.write(reinterpret_cast<const char*>(&sh_degree), 4);
    out.write(reinterpret_cast<const char*>(&length), 8);
  }
  EXPECT_TRUE(ThrowsInputErrorWithinMemory([&path] { ReadCheckpoint(path); }));
  std::remove(path.c_str());
}

// A checkpoint of another scene (its frame order names frames this run does
// not train on) or a corrupt RNG state is an input error, not a crash.
TEST(CheckpointTest, SamplerStateOfAnotherRunIsAnInputError) {
  FrameSampler sampler({0, 2, 4}, 1);
  FrameSampler other({0, 2, 5}, 1);
  other.Next();  // its state now holds an order over frames 0, 2, 5
  EXPECT_THROW(sampler.Restore(other.state()), InputError);
  FrameSampler::State bad_rng = sampler.state();
  bad_rng.rng = "not a generator";
  EXPECT_THROW(sampler.Restore(bad_rng), InputError);
  FrameSampler::State bad_position = sampler.state();
  bad_position.position = -1;
  EXPECT_THROW(sampler.Restore(bad_position), InputError);
  FrameSampler same({4, 0, 2}, 7);
  same.Next();
  sampler.Restore(same.state());  // the same frames in another order: fine
}

TEST(FrameSamplerTest, EpochsArePermutationsAndStateRoundTrips) {
  FrameSampler a({2, 4, 6, 8, 10}, 9), b({2, 4, 6, 8, 10}, 9);
  std::vector<int> seq;
  for (int epoch = 0; epoch < 3; ++epoch) {
    std::set<int> seen;
    for (int i = 0; i < 5; ++i) {
      seq.push_back(a.Next());
      seen.insert(seq.back());
    }
    EXPECT_EQ(seen, (std::set<int>{2, 4, 6, 8, 10}));
  }
  EXPECT_NE(std::vector<int>(seq.begin(), seq.begin() + 5),
            std::vector<int>(seq.begin() + 5, seq.begin() + 10));
  for (int i = 0; i < 7; ++i) EXPECT_EQ(b.Next(), seq[i]);
  FrameSampler c({2, 4, 6, 8, 10}, 1234);
  c.Restore(b.state());
  for (int i = 7; i < 15; ++i) EXPECT_EQ(c.Next(), seq[i]);
}

}  // namespace
}  // namespace es
