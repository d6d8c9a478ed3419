#include "solvers/eval/training_water_psnr.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "core/base/input_error.h"
#include "tests/temp_dir_test.h"

using ::testing::HasSubstr;

namespace es {
namespace {

class TrainingWaterPsnrTest : public TempDirTest {
 protected:
  void Write(const std::string& name, const std::string& text) {
    std::ofstream(Path(name)) << text;
  }
};

// Stage 3's first and last held-out evaluations are the first and last
// rows with a water PSNR; logging rows between evaluations have none.
TEST_F(TrainingWaterPsnrTest, ReadsStageOneAndStageThreesFirstAndLast) {
  Write("metrics.json",
        "{\"psnr_test\": 20.5, \"stage1_psnr_test_water\": 17.78}");
  Write("history.csv",
        "iteration,seconds,loss,psnr_test,psnr_test_water\n"
        "0,0,,20.1,17.69\n"
        "100,3,0.4,,\n"
        "200,6,0.3,19.0,16.2\n"
        "300,9,0.3,,\n"
        "400,12,0.2,19.2,16.7\n"
        "450,13,0.2,,\n");
  const TrainingWaterPsnr p = ReadTrainingWaterPsnr(dir_.string());
  EXPECT_DOUBLE_EQ(p.stage1, 17.78);
  EXPECT_DOUBLE_EQ(p.first, 17.69);
  EXPECT_EQ(p.first_iteration, 0);
  EXPECT_DOUBLE_EQ(p.last, 16.7);
  EXPECT_EQ(p.last_iteration, 400);
  const nlohmann::ordered_json json = TrainingWaterPsnrJson(p);
  EXPECT_DOUBLE_EQ(json["stage3_last"].get<double>(), 16.7);
}

TEST_F(TrainingWaterPsnrTest, MissingRecordsLeaveNaNAndBadJsonIsNamed) {
  TrainingWaterPsnr p = ReadTrainingWaterPsnr(dir_.string());
  EXPECT_TRUE(std::isnan(p.stage1) && std::isnan(p.first));
  EXPECT_EQ(p.first_iteration, -1);
  EXPECT_TRUE(TrainingWaterPsnrJson(p)["stage1"].is_null());
  Write("metrics.json", "{\"psnr_test\": ");
  try {
    ReadTrainingWaterPsnr(dir_.string());
    FAIL() << "a truncated metrics.json was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("metrics.json"));
  }
}

}  // namespace
}  // namespace es
