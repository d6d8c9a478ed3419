// Every app's --threads (apps/common/threads_flag.h): what 0 means, and
// that a binary runs with the threads it was given.

#include "apps/common/threads_flag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <thread>
#include <tuple>

#include "core/base/input_error.h"
#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

TEST(ThreadsFlagTest, ZeroMeansTheEnvironmentElseEveryCore) {
  EXPECT_EQ(ResolvedThreads(3, nullptr), 3);
  EXPECT_EQ(ResolvedThreads(3, "7"), 3) << "the flag wins";
  EXPECT_EQ(ResolvedThreads(0, "7"), 7);
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  EXPECT_EQ(ResolvedThreads(0, nullptr), cores);
  EXPECT_EQ(ResolvedThreads(0, "zero"), cores) << "not a number: ignored";
  EXPECT_EQ(ResolvedThreads(0, "-2"), cores);
}

TEST(ThreadsFlagTest, ANegativeCountIsRefusedByName) {
  try {
    ResolvedThreads(-1, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("--threads=-1")) << e.what();
  }
}

// bench_static prints the OpenMP threads it trains with: --threads sets
// them over OMP_NUM_THREADS, and 0 leaves OMP_NUM_THREADS in charge.
TEST(ThreadsFlagTest, AnAppTrainsWithTheThreadsItIsGiven) {
  const fs::path bin = fs::path(ES_BINARY_DIR) / "bin";
  const fs::path scene = fs::path(ES_BINARY_DIR) /
                         ("threads_flag_test_" + std::to_string(::getpid()));
  fs::remove_all(scene);
  const CommandResult synth =
      RunCommand((bin / "es_synth").string() + " --out " + scene.string() +
                 " --frames 6 --width 32 --height 24 "
                 "--detail 0.02 --num_points 50");
  ASSERT_EQ(synth.status, 0) << synth.output;
  const std::string bench = (bin / "bench_static").string() + " --scene " +
                            scene.string() +
                            " --iterations 2 --eval_every 2";
  for (const auto& [env, flag, expected] :
       {std::tuple{"OMP_NUM_THREADS=2", "--threads 3", "3 threads"},
        std::tuple{"OMP_NUM_THREADS=2", "--threads 1", "1 threads"},
        std::tuple{"OMP_NUM_THREADS=3", "--threads 0", "3 threads"}}) {
    const CommandResult r =
        RunCommand(std::string("env ") + env + " " + bench + " " + flag);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr(std::string(", ") + expected))
        << env << " " << flag << "\n"
        << r.output;
  }
  const CommandResult refused = RunCommand(bench + " --threads -2");
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("--threads=-2: must be >= 0"));
  fs::remove_all(scene);
}

}  // namespace
}  // namespace es
