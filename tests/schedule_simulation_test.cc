#include "core/base/schedule_simulation.h"

#include <numeric>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

TEST(ScheduleSimulationTest, DynamicHandsTheNextIterationToTheFirstFreeThread) {
  // Thread 0 takes the 4, thread 1 the four 1s meanwhile: done at 4.
  EXPECT_EQ(DynamicScheduleMakespan({4, 1, 1, 1, 1}, 2), 4.0);
  // A long last iteration cannot be balanced: 3 + 5 on whichever is free.
  EXPECT_EQ(DynamicScheduleMakespan({1, 1, 1, 1, 1, 1, 5}, 2), 8.0);
  EXPECT_EQ(DynamicScheduleMakespan({1, 1, 1, 1, 1, 1, 5}, 7), 5.0);
  // Chunks of two: {3, 3} to thread 0, {1, 1} to 1, then {1, 1} to 1.
  EXPECT_EQ(DynamicScheduleMakespan({3, 3, 1, 1, 1, 1}, 2, 2), 6.0);
}

TEST(ScheduleSimulationTest, StaticSplitsAsOpenMpDoes) {
  const std::vector<double> costs = {1, 2, 3, 4, 5};
  // schedule(static), 2 threads: {1, 2, 3} and {4, 5}.
  EXPECT_EQ(StaticScheduleMakespan(costs, 2), 9.0);
  // schedule(static, 1): {1, 3, 5} and {2, 4}.
  EXPECT_EQ(StaticScheduleMakespan(costs, 2, 1), 9.0);
  // schedule(static, 2): {1, 2, 5} and {3, 4}.
  EXPECT_EQ(StaticScheduleMakespan(costs, 2, 2), 8.0);
}

TEST(ScheduleSimulationTest, OneThreadTakesTheSumAndManyTheLargest) {
  const std::vector<double> costs = {0.5, 7, 2, 2, 9, 0.25, 3};
  const double sum = std::accumulate(costs.begin(), costs.end(), 0.0);
  EXPECT_EQ(DynamicScheduleMakespan(costs, 1), sum);
  EXPECT_EQ(StaticScheduleMakespan(costs, 1), sum);
  EXPECT_EQ(DynamicScheduleMakespan(costs, 64), 9.0);
  EXPECT_EQ(StaticScheduleMakespan(costs, 64), 9.0);
  for (int threads = 1; threads <= 8; ++threads) {
    EXPECT_GE(DynamicScheduleMakespan(costs, threads), sum / threads);
  }
}

}  // namespace
}  // namespace es
