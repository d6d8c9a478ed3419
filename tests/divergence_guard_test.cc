#include "solvers/train/divergence_guard.h"

#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/expect_error.h"

namespace es {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(DivergenceGuardTest, AllFiniteFindsAnyNanOrInf) {
  std::vector<double> v(1001, 1e308);  // huge but finite
  EXPECT_TRUE(AllFinite(v));
  for (double bad : {kNan, kInf, -kInf}) {
    for (size_t at : {size_t{0}, size_t{500}, size_t{1000}}) {
      std::vector<double> w = v;
      w[at] = bad;
      EXPECT_FALSE(AllFinite(w)) << bad << " at " << at;
    }
  }
  GaussianSet g;
  g.Resize(3);
  EXPECT_TRUE(AllFinite(g));
  g.sh[4] = kNan;
  EXPECT_FALSE(AllFinite(g));
}

TEST(DivergenceGuardTest, SkipsAndCountsAndStopsAfterTooManyInARow) {
  DivergenceGuard guard("test", 3);
  EXPECT_TRUE(guard.Accept(1, true));
  EXPECT_FALSE(guard.Accept(2, false));
  EXPECT_FALSE(guard.Accept(3, false));
  EXPECT_EQ(guard.in_a_row(), 2);
  EXPECT_TRUE(guard.Accept(4, true));  // a good step resets the streak
  EXPECT_EQ(guard.in_a_row(), 0);
  EXPECT_FALSE(guard.Accept(5, false));
  EXPECT_FALSE(guard.Accept(6, false));
  ExpectErrorNaming<TrainingDiverged>(
      [&] { guard.Accept(7, false); },
      {"3 non-finite steps in a row", "iteration 7"});
  EXPECT_EQ(guard.skipped(), 5);
}

TEST(DivergenceGuardTest, NonFiniteParametersStopAtOnce) {
  const DivergenceGuard guard("Stage 1 training");
  guard.CheckParameters(1, true);
  EXPECT_THROW(guard.CheckParameters(2, false), TrainingDiverged);
}

TEST(DivergenceGuardTest, MaxMagnitudeIsTheLargestAbsoluteValueOrInfinity) {
  EXPECT_EQ(MaxMagnitude(std::vector<double>{}), 0.0);
  // 13 values: the eight-lane loop and the tail both see their share.
  std::vector<double> v(13, 0.5);
  for (size_t at : {size_t{2}, size_t{12}}) {
    std::vector<double> w = v;
    w[at] = -3e30;
    EXPECT_EQ(MaxMagnitude(w), 3e30) << at;
  }
  for (double bad : {kNan, kInf, -kInf}) {
    for (size_t at : {size_t{0}, size_t{7}, size_t{12}}) {
      std::vector<double> w = v;
      w[at] = bad;
      EXPECT_EQ(MaxMagnitude(w), kInf) << bad << " at " << at;
    }
  }
  // The bound: kRunawayGrowth times the larger of the floor and the values.
  EXPECT_EQ(RunawayBound(v, 1.0), kRunawayGrowth);
  EXPECT_EQ(RunawayBound(std::vector<double>{-4, 2}, 1.0),
            4 * kRunawayGrowth);
}

// Finite garbage (es_static --lr_position 1e30 left the means at 1e30 and
// exited 0) stops the run with a message naming the learning rate.
TEST(DivergenceGuardTest, RunawayBlockStopsNamingItsLearningRate) {
  const DivergenceGuard guard("Stage 1 training");
  const GuardedBlock means{"the Gaussians' means", "the position learning rate",
                           "--lr_position", 1e30, 2e6};
  guard.CheckRunaway(3, means, 2e6);  // at the bound: fine
  ExpectErrorNaming<TrainingDiverged>(
      [&] { guard.CheckRunaway(4, means, 3e30); },
      {"Stage 1 training diverged at iteration 4", "the Gaussians' means",
       "3e+30", "the position learning rate", "--lr_position 1e+30",
       "lower it"});
  // CheckBlocks: a non-finite block is CheckParameters' error first.
  const GuardedBlock sh{"the SH", "an SH learning rate", "--lr_sh_dc", 1, 1e6};
  guard.CheckBlocks(5, {means, sh}, {1.0, 1.0});
  ExpectErrorNaming<TrainingDiverged>(
      [&] { guard.CheckBlocks(6, {means, sh}, {1.0, kInf}); }, {"non-finite"});
  EXPECT_THROW(guard.CheckBlocks(7, {means, sh}, {1.0, 2e6}),
               TrainingDiverged);
}

TEST(DivergenceGuardTest, LossGrowingOrdersOfMagnitudeStops) {
  const DivergenceGuard guard("V pretraining");
  const std::vector<GuardedBlock> blocks = {
      {"V's triplane", "the triplane learning rate", "--lr_triplane", 0.01, 1},
      {"V's MLP", "the MLP learning rate", "--lr_mlp", 1e30, 1}};
  guard.CheckLoss(1, 0.5, 0.5, blocks);
  guard.CheckLoss(2, 0.5 * kLossGrowth, 0.5, blocks);  // at the limit
  ExpectErrorNaming<TrainingDiverged>(
      [&] { guard.CheckLoss(3, 1e60, 0.5, blocks); },
      {"iteration 3", "1e+60", "--lr_triplane 0.01", "--lr_mlp 1e+30"});
}

}  // namespace
}  // namespace es
