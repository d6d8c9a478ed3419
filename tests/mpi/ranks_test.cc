// Run under mpiexec (ctest runs it on 2 ranks): data-parallel training
// over the ranks (Stages 1, 2 and 3) gives the model that one process gets
// with the same batch. With two ranks the sum over them is the one
// process's sum, so the models are equal bit for bit; more ranks may only
// reassociate it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "core/base/communicator.h"
#include "core/base/mpi/mpi_world.h"
#include "solvers/train/data_parallel.h"
#include "solvers/train/flow_pretrain.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/static_trainer.h"
#include "tests/expect_same_gaussians.h"
#include "tests/random_scene_flow_samples.h"
#include "tests/small_motion_field.h"
#include "tests/tiny_loop_scene.h"

namespace es {
namespace {

using namespace tiny_loop;  // NOLINT: the scene's constants

Communicator* world = nullptr;

const std::vector<int> kTrain = {0, 1, 2, 4, 5, 7, 8, 9, 10};

// Frames per iteration: two, or one per rank on more ranks.
int BatchFrames() { return std::max(2, world->size()); }

// Exactly equal on two ranks; to reassociation on more.
void ExpectSameValues(const std::vector<double>& ranks,
                      const std::vector<double>& one, const char* what) {
  ASSERT_EQ(ranks.size(), one.size()) << what;
  if (world->size() <= 2) {
    EXPECT_EQ(ranks, one) << what;
    return;
  }
  for (size_t i = 0; i < one.size(); ++i)
    EXPECT_NEAR(ranks[i], one[i], 1e-9 * (1 + std::abs(one[i]))) << what;
}

// Rank 0's values on every rank: the ranks stepped alike.
void ExpectRanksAgree(const std::vector<double>& values, const char* what) {
  std::vector<double> lead = values;
  world->Broadcast(lead.data(), lead.size() * sizeof(double), 0);
  EXPECT_EQ(values, lead) << what << " differs on rank " << world->rank();
}

TEST(RanksTest, StaticTrainingOnRanksEqualsOneProcess) {
  const std::vector<Frame> frames = TrueFrames();
  StaticTrainerOptions options;
  options.iterations = 60;
  options.seed = 7;
  options.batch_frames = BatchFrames();
  // Densification within the run: the views' statistics are summed over
  // the ranks too.
  options.densify_options.from_iteration = 5;
  options.densify_options.interval = 10;
  options.densify_options.grad_threshold = 1e-6;
  options.densify_options.opacity_reset_interval = 25;
  GaussianSet start = TrueCanonical();
  for (double& m : start.means) m += 0.03;
  StaticTrainer alone(&frames, kTrain, options, start);
  options.comm = world;
  StaticTrainer ranks(&frames, kTrain, options, start);
  for (int i = 0; i < options.iterations; ++i) {
    const IterationStats a = alone.Step();
    const IterationStats r = ranks.Step();
    ASSERT_EQ(a.frame, r.frame);
    if (world->size() <= 2) {
      ASSERT_EQ(a.loss, r.loss) << "iteration " << i;
    }
  }
  ASSERT_GT(alone.gaussians().size(), start.size()) << "no densification";
  ASSERT_EQ(ranks.gaussians().size(), alone.gaussians().size());
  ExpectSameValues(AllGaussianValues(ranks.gaussians()),
                   AllGaussianValues(alone.gaussians()), "splats");
  ExpectRanksAgree(AllGaussianValues(ranks.gaussians()), "splats");
}

TEST(RanksTest, JointTrainingOnRanksEqualsOneProcess) {
  const std::vector<Frame> frames = TrueFrames();
  JointTrainerOptions options = TinyOptions();
  options.iterations = 30;
  options.seed = 4;
  options.water_energy = WaterEnergyOptions();  // pairs of frames
  options.water_densify.interval = 5;  // the water grows between steps
  options.batch_frames = BatchFrames();
  ASSERT_TRUE(PairLossOn(options));
  GaussianSet start = TrueCanonical();
  for (double& m : start.means) m += 0.02;
  JointTrainer alone(&frames, kTrain, options, start, std::nullopt);
  options.comm = world;
  JointTrainer ranks(&frames, kTrain, options, start, std::nullopt);
  for (int i = 0; i < options.iterations; ++i) {
    const JointIterationStats a = alone.Step();
    const JointIterationStats r = ranks.Step();
    ASSERT_EQ(a.frame, r.frame);
    if (world->size() <= 2) {
      ASSERT_EQ(a.loss, r.loss) << "iteration " << i;
    }
  }
  LoopModel a = alone.model(), r = ranks.model();
  ASSERT_GT(a.gaussians.size(), start.size()) << "no water densification";
  ASSERT_EQ(r.gaussians.size(), a.gaussians.size());
  ExpectSameValues(AllGaussianValues(r.gaussians),
                   AllGaussianValues(a.gaussians),
                   "splats");
  const std::vector<std::vector<double>*> fields_a = FieldParamBlocks(&a);
  const std::vector<std::vector<double>*> fields_r = FieldParamBlocks(&r);
  ASSERT_EQ(fields_a.size(), 4u);  // V and D, triplane and MLP each
  for (size_t b = 0; b < fields_a.size(); ++b) {
    ExpectSameValues(*fields_r[b], *fields_a[b], "a field block");
    ExpectRanksAgree(*fields_r[b], "a field block");
  }
  ExpectRanksAgree(AllGaussianValues(r.gaussians), "splats");
}

TEST(RanksTest, PackedSumSendsOnlyChunksSomeRankHoldsNonZero) {
  if (world->size() < 2) GTEST_SKIP() << "needs 2 ranks";
  // Four chunks: one non-zero on this rank only, one on every rank, one
  // nowhere, one NaN on rank 1 only.
  const size_t n = 4 * kSumChunk;
  PackedSum sum;
  sum.Reset({n - 3, 3});
  std::vector<double> a(n - 3, 0.0);
  a[world->rank() % 2 == 0 ? 1 : kSumChunk + 2] = 1.5 + world->rank();
  a[kSumChunk + 5] = 1.0;
  if (world->rank() == 1) a[3 * kSumChunk] = std::nan("");
  sum.Add(0, a.data());
  sum.AllreduceSum(world);
  std::vector<double> expected(n - 3, 0.0);
  for (int r = 0; r < world->size(); ++r)
    expected[r % 2 == 0 ? 1 : kSumChunk + 2] += 1.5 + r;
  expected[kSumChunk + 5] = world->size();
  for (size_t i = 0; i < n - 3; ++i) {
    if (i == 3 * kSumChunk) {
      EXPECT_TRUE(std::isnan(sum.data()[i]));  // a NaN reaches every rank
    } else {
      EXPECT_EQ(sum.data()[i], expected[i]) << i;
    }
  }
  // The flags and three chunks of 64 doubles, not four.
  EXPECT_EQ(sum.bytes_per_reduction(), 4 + 3 * kSumChunk * sizeof(double));
}

TEST(RanksTest, FlowPretrainingOnRanksEqualsOneProcessWithAsManyShards) {
  const std::vector<SceneFlowSample> samples =
      RandomSceneFlowSamples(600, 3, 0.8, 0.05);
  FlowPretrainOptions options;
  options.iterations = 40;
  options.batch_size = 150;
  options.seed = 5;
  options.log_every = 0;
  options.shards = world->size();
  MotionField alone = SmallMotionField(9), ranks = SmallMotionField(9);
  const FlowPretrainReport a = PretrainMotionField(samples, options, &alone);
  options.comm = world;
  const FlowPretrainReport r = PretrainMotionField(samples, options, &ranks);
  ExpectSameValues(ranks.triplane_params(), alone.triplane_params(),
                   "V's triplane");
  ExpectSameValues(ranks.mlp_params(), alone.mlp_params(), "V's MLP");
  ExpectRanksAgree(ranks.triplane_params(), "V's triplane");
  ExpectRanksAgree(ranks.mlp_params(), "V's MLP");
  EXPECT_LT(r.fit_rmse, r.initial_rmse);  // it did fit
  if (world->size() <= 2) {
    EXPECT_EQ(r.fit_rmse, a.fit_rmse);
  }
  // The shards' sum is the whole batch's but for reassociation, which
  // Adam's steps may amplify: the fit is as good.
  options.comm = nullptr;
  options.shards = 1;
  MotionField whole = SmallMotionField(9);
  const FlowPretrainReport w = PretrainMotionField(samples, options, &whole);
  EXPECT_NEAR(r.fit_rmse, w.fit_rmse, 0.05 * w.fit_rmse);
}

TEST(RanksTest, SplitMakesGroupsThatSumOnlyTheirOwnRanks) {
  // Two groups, even and odd ranks (one scene each in a batch of scenes).
  const int color = world->rank() % 2;
  std::unique_ptr<Communicator> group = world->Split(color);
  EXPECT_EQ(group->size(), (world->size() + 1 - color) / 2);
  EXPECT_EQ(group->rank(), world->rank() / 2);
  double sum[2] = {1, static_cast<double>(world->rank())};
  group->AllreduceSum(sum, 2);
  double expected = 0;
  for (int r = color; r < world->size(); r += 2) expected += r;
  EXPECT_EQ(sum[0], group->size());
  EXPECT_EQ(sum[1], expected);
  float f = 1;
  group->AllreduceSum(&f, 1);
  EXPECT_EQ(f, group->size());
  double top = world->rank();
  world->AllreduceMax(&top, 1);
  EXPECT_EQ(top, world->size() - 1);
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  std::unique_ptr<es::Communicator> world = es::MpiWorld(&argc, &argv);
  es::world = world.get();
  if (world->rank() != 0) {  // one report, rank 0's
    testing::TestEventListeners& listeners =
        testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  double failed = RUN_ALL_TESTS() != 0;
  world->AllreduceMax(&failed, 1);  // a failure on any rank fails the test
  return failed > 0 ? 1 : 0;
}
