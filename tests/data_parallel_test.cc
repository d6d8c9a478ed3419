// A batch of B frames in one process steps on the mean of the B frames'
// own gradients (solvers/train/data_parallel.h), in Stage 1 and in Stage 3
// with the pair terms, whose halving belongs to one frame's pair only; the
// checkpoints keep B.

#include "solvers/train/data_parallel.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <vector>

#include "core/base/communicator.h"
#include "core/base/input_error.h"
#include "costs/joint_objective.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/static_stage.h"
#include "solvers/train/static_trainer.h"
#include "synth/scene.h"
#include "synth/writer.h"
#include "tests/expect_same_gaussians.h"
#include "tests/max_abs_diff.h"
#include "tests/temp_dir_test.h"
#include "tests/tiny_loop_scene.h"
#include "tests/tiny_synth_settings.h"

using ::testing::HasSubstr;

namespace es {
namespace {

using namespace tiny_loop;  // NOLINT: the scene's constants

const std::vector<int> kTrain = {0, 1, 2, 4, 5, 7, 8, 9, 10};

// Largest |a - b| over the largest |b| (1 when b is all zero).
double RelativeError(const std::vector<double>& a,
                     const std::vector<double>& b) {
  const AbsDiff d = MaxAbsDiff(a, b);
  return d.diff / (d.scale > 0 ? d.scale : 1);
}

TEST(DataParallelTest, PackedSumKeepsSegmentsApart) {
  PackedSum sum;
  sum.Reset({2, 0, 3});
  ASSERT_EQ(sum.segments(), 3);
  const double a[2] = {1, 2}, b[3] = {3, 4, 5};
  sum.Add(0, a);
  sum.Add(2, b);
  sum.Add(2, b);
  sum.Divide(2, 2);
  sum.AllreduceSum(&SingleProcess());
  EXPECT_EQ(sum.data(), (std::vector<double>{1, 2, 3, 4, 5}));
}

TEST(DataParallelTest, BatchNeedsAFramePerRank) {
  // A communicator of 3 ranks (never reduces: only its size is read).
  class ThreeRanks : public SingleProcessCommunicator {
    int size() const override { return 3; }
  } three;
  EXPECT_THROW(CheckBatchFrames(2, three), InputError);
  EXPECT_THROW(CheckBatchFrames(0, SingleProcess()), InputError);
  EXPECT_NO_THROW(CheckBatchFrames(3, three));
  // Frame k of a batch goes to rank k mod 3.
  EXPECT_TRUE(RendersBatchFrame(three, 0));
  EXPECT_FALSE(RendersBatchFrame(three, 1));
  EXPECT_TRUE(RendersBatchFrame(three, 3));
}

TEST(DataParallelTest, StaticBatchStepsOnTheMeanOfItsFramesGradients) {
  const std::vector<Frame> frames = TrueFrames();
  StaticTrainerOptions options;
  options.batch_frames = 3;
  options.seed = 5;
  // Wrong splats, so every frame has a gradient of its own.
  GaussianSet start = TrueCanonical();
  for (double& m : start.means) m += 0.03;
  StaticTrainer trainer(&frames, kTrain, options, start);
  const IterationStats stats = trainer.Step();
  ASSERT_FALSE(stats.skipped);

  // The same three frames, each on its own.
  FrameSampler sampler(kTrain, options.seed);
  const bool masks = AllHaveMasks(frames, kTrain);
  Rasterizer rasterizer;
  std::vector<double> mean;
  double mean_loss = 0;
  std::vector<std::vector<double>> each;
  for (int k = 0; k < 3; ++k) {
    const Frame& frame = frames[sampler.Next()];
    GaussianSet g = start, grad = ZeroGaussians(start.size(), start.sh_degree);
    SplatRenderCost cost(&frame, g.size(), g.sh_degree,
                         StaticLossTerms(options, masks),
                         StaticRenderOptions(options), &rasterizer);
    std::vector<double*> params = SplatRenderCost::Blocks(&g);
    std::vector<double*> gradients = SplatRenderCost::Blocks(&grad);
    mean_loss +=
        EvaluateScalarLossGradient(cost, params.data(), gradients.data()) / 3;
    each.push_back(AllGaussianValues(grad));
    if (mean.empty()) mean.assign(each.back().size(), 0.0);
    for (size_t i = 0; i < mean.size(); ++i) mean[i] += each.back()[i] / 3;
  }
  EXPECT_LT(
      RelativeError(AllGaussianValues(trainer.last_gradient()), mean),
      1e-12);
  EXPECT_NEAR(stats.loss, mean_loss, 1e-12 * mean_loss);
  // Not one frame's gradient alone.
  for (const std::vector<double>& one : each)
    EXPECT_GT(RelativeError(one, mean), 1e-3);
}

TEST(DataParallelTest, JointPairBatchStepsOnTheMeanOfItsFramesGradients) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.water_energy = WaterEnergyOptions();  // the pair terms on
  options.batch_frames = 2;
  ASSERT_TRUE(PairLossOn(options));
  // A seed whose batch holds two different pairs of frames.
  const std::vector<int> partner = TrainingNeighbours(frames, kTrain);
  for (options.seed = 0;; ++options.seed) {
    FrameSampler draw(kTrain, options.seed);
    const int a = draw.Next(), b = draw.Next();
    if (std::min(a, partner[a]) != std::min(b, partner[b]) ||
        std::max(a, partner[a]) != std::max(b, partner[b]))
      break;
  }
  GaussianSet start = TrueCanonical();
  for (double& m : start.means) m += 0.02;
  // Two trainers from the same seed start from the same model: one steps,
  // the other's model is the one the gradients are taken at.
  JointTrainer trainer(&frames, kTrain, options, start, std::nullopt);
  JointTrainer twin(&frames, kTrain, options, start, std::nullopt);
  const JointIterationStats stats = trainer.Step();
  ASSERT_FALSE(stats.skipped);

  LoopModel model = twin.model();
  const bool masks = options.mask_weight > 0 && AllHaveMasks(frames, kTrain);
  const bool water_masks =
      WaterLossOn(options) && AllHaveMasks(frames, kTrain);
  JointObjective objective(&frames[kTrain[0]], LoopStructure::Of(model),
                           JointObjectiveOptionsOf(options, masks,
                                                   water_masks));
  const std::vector<int32_t>& sizes = objective.layout().sizes();
  FrameSampler sampler(kTrain, options.seed);
  std::vector<double> mean;
  std::vector<std::vector<double>> each;
  for (int k = 0; k < 2; ++k) {
    const int f = sampler.Next();
    ASSERT_GE(partner[f], 0);
    std::vector<std::vector<double>> grad;
    std::vector<double*> gradients;
    for (int32_t size : sizes) grad.emplace_back(size, 0.0);
    for (std::vector<double>& g : grad) gradients.push_back(g.data());
    JointObjectiveTerms terms;
    std::vector<double*> params = JointBlocks(&model);
    objective.EvaluateFrame(LoopStructure::Of(model), params.data(),
                            frames[f], &frames[partner[f]],
                            WaterLossRamp(options, 0), 0, gradients.data(),
                            nullptr, &terms);
    std::vector<double> flat;
    for (const std::vector<double>& g : grad)
      flat.insert(flat.end(), g.begin(), g.end());
    each.push_back(flat);
    if (mean.empty()) mean.assign(flat.size(), 0.0);
    for (size_t i = 0; i < flat.size(); ++i) mean[i] += flat[i] / 2;
  }
  std::vector<double> batch = trainer.last_batch_gradient();
  batch.resize(mean.size());  // the loss terms follow the blocks
  EXPECT_LT(RelativeError(batch, mean), 1e-12);
  // The fields' part too (a pair halves its own sum, not the batch's).
  const size_t splats = std::accumulate(sizes.begin(),
                                        sizes.begin() + kNumSplatBlocks,
                                        size_t{0});
  const std::vector<double> fields_batch(batch.begin() + splats, batch.end());
  const std::vector<double> fields_mean(mean.begin() + splats, mean.end());
  ASSERT_FALSE(fields_mean.empty());
  EXPECT_LT(RelativeError(fields_batch, fields_mean), 1e-12);
  for (const std::vector<double>& one : each)
    EXPECT_GT(RelativeError(one, mean), 1e-3);
}

// The checkpoints keep the batch size, and a resume with another is
// refused before any work: its batches would draw other frames.
class BatchCheckpointTest : public TempDirTest {};

TEST_F(BatchCheckpointTest, ResumeWithAnotherBatchSizeIsRefused) {
  WriteSynthScene(GenerateSynthScene(TinySynthSettings()), Path("scene"));
  StaticStageOptions o;
  o.scene_dir = Path("scene");
  o.out_dir = Path("out");
  o.checkpoint_every = 2;
  o.log_every = 0;
  o.eval_every = 0;
  o.trainer.iterations = 2;
  o.trainer.batch_frames = 2;
  RunStaticStage(o);
  EXPECT_EQ(ReadCheckpoint(Path("out/checkpoint.bin")).batch_frames, 2);
  o.resume = true;
  o.trainer.iterations = 4;
  o.trainer.batch_frames = 1;
  try {
    RunStaticStage(o);
    FAIL() << "a resume with another batch size went on";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("--batch_frames 2, this one has 1"))
        << e.what();
  }
  o.trainer.batch_frames = 2;
  EXPECT_EQ(RunStaticStage(o).num_gaussians,
            ReadCheckpoint(Path("out/checkpoint.bin")).gaussians.size());
}

TEST_F(BatchCheckpointTest, JointCheckpointKeepsTheBatchSize) {
  JointCheckpoint c;
  c.batch_frames = 3;
  c.sampler.rng = "1";
  WriteJointCheckpoint(c, Path("joint.bin"));
  EXPECT_EQ(ReadJointCheckpoint(Path("joint.bin")).batch_frames, 3);
  EXPECT_NO_THROW(CheckResumedBatch(3, 3, "joint.bin"));
  EXPECT_THROW(CheckResumedBatch(3, 2, "joint.bin"), InputError);
}

}  // namespace
}  // namespace es
