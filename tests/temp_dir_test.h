#ifndef EULERSPLAT_TESTS_TEMP_DIR_TEST_H_
#define EULERSPLAT_TESTS_TEMP_DIR_TEST_H_

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace es {

// Fixture with a fresh, empty directory per test (named after the suite,
// the test and the process, so parallel ctest runs never share one),
// removed when the test ends.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* test =
        ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("es_" + std::string(test->test_suite_name()) + "_" +
            test->name() + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  std::filesystem::path dir_;
};

}  // namespace es

#endif  // EULERSPLAT_TESTS_TEMP_DIR_TEST_H_
