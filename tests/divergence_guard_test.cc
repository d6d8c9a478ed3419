#include "solvers/train/divergence_guard.h"

#include <limits>
#include <vector>

#include <gtest/gtest.h>

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
  try {
    guard.Accept(7, false);
    ADD_FAILURE() << "no TrainingDiverged";
  } catch (const TrainingDiverged& e) {
    EXPECT_NE(std::string(e.what()).find("3 non-finite steps in a row"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("iteration 7"), std::string::npos);
  }
  EXPECT_EQ(guard.skipped(), 5);
}

TEST(DivergenceGuardTest, NonFiniteParametersStopAtOnce) {
  const DivergenceGuard guard("Stage 1 training");
  guard.CheckParameters(1, true);
  EXPECT_THROW(guard.CheckParameters(2, false), TrainingDiverged);
}

}  // namespace
}  // namespace es
