// JSON outputs (core/io/json_file.h) and the output-folder check.

#include "core/io/json_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "tests/temp_dir_test.h"

using ::testing::HasSubstr;
using ::testing::Not;

namespace es {
namespace {

using JsonFileTest = TempDirTest;

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(JsonFileTest, NonFiniteNumbersBecomeNullAndPathsAreEscaped) {
  const std::string odd_path = "dir \"quoted\"\\back\nslash";
  WriteJsonFile(Path("m.json"), {{"psnr", NAN},
                                 {"ssim", -INFINITY},
                                 {"seconds", 1.5},
                                 {"model", odd_path}});
  const std::string text = Read(Path("m.json"));
  EXPECT_THAT(text, Not(HasSubstr("nan")));
  EXPECT_THAT(text, Not(HasSubstr("inf")));
  const nlohmann::json back = nlohmann::json::parse(text);  // throws if bad
  EXPECT_TRUE(back["psnr"].is_null());
  EXPECT_TRUE(back["ssim"].is_null());
  EXPECT_EQ(back["seconds"], 1.5);
  EXPECT_EQ(back["model"], odd_path);
}

TEST_F(JsonFileTest, InvalidUtf8StillGivesValidJson) {
  WriteJsonFile(Path("u.json"), {{"scene", std::string("bad\xff\xfe")}});
  EXPECT_NO_THROW(nlohmann::json::parse(Read(Path("u.json"))));
}

// A full disk, simulated with a file-size limit: the write must fail loudly
// and leave the previous file as it was.
TEST_F(JsonFileTest, AFullDiskIsAnErrorAndKeepsTheOldFile) {
  WriteJsonFile(Path("big.json"), {{"old", true}});
  const std::string before = Read(Path("big.json"));
  nlohmann::ordered_json big;
  big["values"] = std::vector<double>(20000, 0.123456789);

  std::signal(SIGXFSZ, SIG_IGN);  // a failed write, not a killed process
  rlimit saved;
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    WriteJsonFile(Path("big.json"), big);
  } catch (const InputError& e) {
    threw = true;
    EXPECT_THAT(std::string(e.what()), HasSubstr("big.json"));
  }
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &saved), 0);
  std::signal(SIGXFSZ, SIG_DFL);
  EXPECT_TRUE(threw) << "a write past the size limit went unnoticed";
  EXPECT_EQ(Read(Path("big.json")), before);
}

TEST_F(JsonFileTest, OutputDirectoryIsCreatedAndChecked) {
  EXPECT_NO_THROW(PrepareOutputDirectory(Path("a/b/c"), "out"));
  EXPECT_TRUE(std::filesystem::is_directory(Path("a/b/c")));
  EXPECT_TRUE(std::filesystem::is_empty(Path("a/b/c")));  // probe removed
  { std::ofstream(Path("file")) << "x"; }
  try {
    PrepareOutputDirectory(Path("file/sub"), "out");
    FAIL() << "a directory below a file was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("--out=")) << e.what();
  }
  EXPECT_THROW(PrepareOutputDirectory(Path("file"), "out"), InputError);
}

}  // namespace
}  // namespace es
