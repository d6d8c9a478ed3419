#include "solvers/optim/sparse_adam.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/fields/gradient_chunks.h"

namespace es {
namespace {

// A sparse gradient: a few runs of non-zero values (a texel's channels),
// different each step, some steps none at all in most of the block.
std::vector<double> SparseGradient(int n, int step, std::mt19937* rng) {
  std::vector<double> g(n, 0.0);
  std::uniform_int_distribution<int> start(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int run = 0; run < 3 + step % 4; ++run) {
    const int s = start(*rng);
    for (int i = s; i < std::min(n, s + 12); ++i) g[i] = value(*rng);
  }
  return g;
}

TEST(SparseAdamTest, MatchesAdamUpdateValueForValueAndClearsTheGradient) {
  const int n = 5000;  // not a multiple of the chunk size
  std::vector<double> x(n), x_dense(n), m(n, 0.0), v(n, 0.0);
  for (int i = 0; i < n; ++i) x[i] = x_dense[i] = std::sin(0.01 * i);
  SparseAdam adam(n);
  std::mt19937 rng(7);
  for (int t = 1; t <= 40; ++t) {
    const double lr = 0.01 / t;
    std::vector<double> g = SparseGradient(n, t, &rng);
    const std::vector<double> g_dense = g;
    ASSERT_TRUE(adam.ScanGradient(g.data()));
    ASSERT_TRUE(adam.Step(t, lr, g.data(), x.data()));
    AdamUpdate(AdamOptions(), t, lr, n, g_dense.data(), m.data(), v.data(),
               x_dense.data());
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(x[i], x_dense[i]) << "step " << t << " value " << i;
      ASSERT_EQ(g[i], 0.0) << "step " << t << " value " << i;
    }
  }
  EXPECT_EQ(adam.m(), m);
  EXPECT_EQ(adam.v(), v);
}

TEST(SparseAdamTest, RestoredMomentsContinueAsTheUninterruptedRun) {
  const int n = 700;
  std::vector<double> x(n, 0.5), x_resumed;
  SparseAdam adam(n);
  std::mt19937 rng(3);
  std::vector<std::vector<double>> grads;
  for (int t = 1; t <= 20; ++t) grads.push_back(SparseGradient(n, t, &rng));
  SparseAdam resumed(n);
  for (int t = 1; t <= 20; ++t) {
    if (t == 11) {
      resumed.Restore(adam.m(), adam.v());
      x_resumed = x;
    }
    std::vector<double> g = grads[t - 1];
    adam.ScanGradient(g.data());
    adam.Step(t, 0.01, g.data(), x.data());
    if (t >= 11) {
      g = grads[t - 1];
      resumed.ScanGradient(g.data());
      resumed.Step(t, 0.01, g.data(), x_resumed.data());
    }
  }
  EXPECT_EQ(x_resumed, x);
}

TEST(SparseAdamTest, NonFiniteGradientsAndParametersAreReported) {
  const int n = 300;
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    SparseAdam adam(n);
    std::vector<double> g(n, 0.0), x(n, 1.0);
    g[5] = 0.1;
    g[250] = bad;
    EXPECT_FALSE(adam.ScanGradient(g.data())) << bad;
    // Dropping the step clears what the scan saw.
    adam.ClearGradient(g.data());
    for (double value : g) ASSERT_EQ(value, 0.0);
    // A finite gradient that takes a parameter to a non-finite value.
    g[7] = 1.0;
    x[7] = bad;
    EXPECT_TRUE(adam.ScanGradient(g.data()));
    EXPECT_FALSE(adam.Step(1, 0.01, g.data(), x.data())) << bad;
  }
}

// A producer that flags the chunks it writes: ScanFlagged gives the same
// steps as the full scan, catches a non-finite value in a flagged chunk,
// and the flags are clear again after Step and after ClearGradient.
TEST(SparseAdamTest, FlaggedScanMatchesTheFullScan) {
  const int n = 5000;
  std::vector<double> x(n), x_full(n);
  for (int i = 0; i < n; ++i) x[i] = x_full[i] = std::cos(0.02 * i);
  SparseAdam flagged(n), full(n);
  std::mt19937 rng(11);
  for (int t = 1; t <= 30; ++t) {
    std::vector<double> g = SparseGradient(n, t, &rng);
    std::vector<double> g_full = g;
    char* flags = flagged.chunk_flags();
    for (int c = 0; c < NumGradientChunks(n); ++c) ASSERT_EQ(flags[c], 0);
    for (int i = 0; i < n; ++i) {
      if (g[i] != 0.0) FlagGradientChunks(i, i + 1, flags);
    }
    // A flagged chunk whose values cancelled to zero.
    FlagGradientChunks(64 * (t % 70), 64 * (t % 70) + 1, flags);
    ASSERT_TRUE(flagged.ScanFlagged(g.data()));
    ASSERT_TRUE(full.ScanGradient(g_full.data()));
    ASSERT_TRUE(flagged.Step(t, 0.01, g.data(), x.data()));
    ASSERT_TRUE(full.Step(t, 0.01, g_full.data(), x_full.data()));
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(x[i], x_full[i]) << "step " << t << " value " << i;
      ASSERT_EQ(g[i], 0.0);
    }
  }
  EXPECT_EQ(flagged.m(), full.m());
  EXPECT_EQ(flagged.v(), full.v());

  std::vector<double> g(n, 0.0);
  g[4000] = std::numeric_limits<double>::quiet_NaN();
  FlagGradientChunks(4000, 4001, flagged.chunk_flags());
  EXPECT_FALSE(flagged.ScanFlagged(g.data()));
  flagged.ClearGradient(g.data());
  for (double value : g) ASSERT_EQ(value, 0.0);
  for (int c = 0; c < NumGradientChunks(n); ++c)
    ASSERT_EQ(flagged.chunk_flags()[c], 0);
}

}  // namespace
}  // namespace es
