// Training histories (history.csv), the CSV tables behind them and the
// Stage-1 ETA that accounts for densification.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/base/input_error.h"
#include "core/io/csv_table.h"
#include "solvers/train/densify_eta.h"
#include "solvers/train/training_history.h"
#include "tests/temp_dir_test.h"

using ::testing::HasSubstr;

namespace es {
namespace {

using HistoryTest = TempDirTest;

TEST_F(HistoryTest, CsvRoundTripKeepsGapsAsNaN) {
  CsvTable table;
  table.columns = {"iteration", "psnr"};
  table.rows = {{1, NAN}, {2, 21.5}};
  {
    std::ofstream out(Path("t.csv"));
    out << CsvText(table);
  }
  const CsvTable back = ReadCsvTable(Path("t.csv"));
  EXPECT_EQ(back.columns, table.columns);
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_TRUE(std::isnan(back.rows[0][1]));
  EXPECT_EQ(back.rows[1][1], 21.5);
  EXPECT_EQ(back.Column("psnr"), 1);
  EXPECT_EQ(back.Column("nope"), -1);
}

TEST_F(HistoryTest, BadCsvNamesTheLine) {
  {
    std::ofstream out(Path("bad.csv"));
    out << "a,b\n1,2\n3,x\n";
  }
  try {
    ReadCsvTable(Path("bad.csv"));
    FAIL() << "accepted a non-number";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("bad.csv:3")) << e.what();
  }
  {
    std::ofstream out(Path("short.csv"));
    out << "a,b\n1\n";
  }
  EXPECT_THROW(ReadCsvTable(Path("short.csv")), InputError);
}

TEST_F(HistoryTest, ResumeDropsRowsPastTheCheckpointAndContinuesTheClock) {
  TrainingHistory first(Path("history.csv"), {"loss"});
  for (int it = 100; it <= 500; it += 100) first.Add(it, it / 10.0, {1.0});
  first.Write();

  // Killed after 500, resumed from the checkpoint at 300.
  TrainingHistory resumed(Path("history.csv"), {"loss"});
  EXPECT_EQ(resumed.Resume(300), 30.0);
  ASSERT_EQ(resumed.table().rows.size(), 3u);
  resumed.Add(400, 30.0 + 12.0, {0.5});
  resumed.SetFinalMetrics(400, 42.0, {{"loss", 0.25}});
  resumed.Write();
  const CsvTable table = ReadCsvTable(Path("history.csv"));
  ASSERT_EQ(table.rows.size(), 4u);
  EXPECT_EQ(table.rows.back()[0], 400);
  EXPECT_EQ(table.rows.back()[1], 42.0);
  EXPECT_EQ(table.rows.back()[2], 0.25);

  // A file with other columns is not continued.
  TrainingHistory other(Path("history.csv"), {"rmse"});
  EXPECT_EQ(other.Resume(300), 0.0);
  EXPECT_TRUE(other.table().rows.empty());
}

TEST(DensifyEtaTest, WithoutGrowthItIsRemainingTimesRate) {
  DensifyEtaInput in;
  in.iteration = 100;
  in.iterations = 1100;
  in.seconds_per_iteration = 0.5;
  in.gaussians = 1000;
  in.growth_per_iteration = 0;
  in.densify_end = 500;
  in.max_gaussians = 1e6;
  EXPECT_DOUBLE_EQ(DensifyingEta(in), 500.0);
  // Pruning (negative growth) does not shorten the projection.
  in.growth_per_iteration = -3;
  EXPECT_DOUBLE_EQ(DensifyingEta(in), 500.0);
}

TEST(DensifyEtaTest, GrowthUntilDensificationEndsIsCounted) {
  DensifyEtaInput in;
  in.iteration = 0;
  in.iterations = 20;
  in.seconds_per_iteration = 1.0;  // with 10 Gaussians
  in.gaussians = 10;
  in.growth_per_iteration = 1;
  in.densify_end = 10;
  in.max_gaussians = 1e6;
  // 11 + 12 + ... + 20 while densifying, then 10 iterations at 20, all at
  // 0.1 s per Gaussian-iteration.
  EXPECT_NEAR(DensifyingEta(in), 0.1 * (155 + 200), 1e-9);
  // The cap stops the growth.
  in.max_gaussians = 15;
  EXPECT_NEAR(DensifyingEta(in), 0.1 * (11 + 12 + 13 + 14 + 15 * 16), 1e-9);
  // Past the end of densification only the rate matters.
  in.iteration = 12;
  EXPECT_NEAR(DensifyingEta(in), 8.0, 1e-9);
}

}  // namespace
}  // namespace es
