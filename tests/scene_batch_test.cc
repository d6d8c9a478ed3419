// eulersplat --scenes: a batch of scenes on groups of ranks
// (apps/common/driver_batch.h). Two tiny scenes and a broken one on 2
// ranks: each good scene gets its whole run in OUT/<name>, the broken one
// is reported without stopping the others, and the batch exits 1; bad
// batches stop before any work.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/common/driver_batch.h"
#include "core/base/input_error.h"
#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

TEST(SceneBatchTest, GroupsShareTheRanksEvenly) {
  EXPECT_EQ(GroupRanks(2, 2), (std::vector<int>{1, 1}));
  EXPECT_EQ(GroupRanks(5, 2), (std::vector<int>{3, 2}));
  EXPECT_EQ(GroupRanks(4, 1), (std::vector<int>{4}));
  EXPECT_EQ(SceneName("/data/fountain/"), "fountain");
  EXPECT_EQ(ParseSceneList(" a, b ,,c"),
            (std::vector<std::string>{"a", "b", "c"}));
}

TEST(SceneBatchTest, BadBatchesAreRefusedBeforeAnyWork) {
  const fs::path root =
      FreshBuildDir("scene_batch_bad_" + std::to_string(::getpid()));
  fs::create_directories(root / "a");
  fs::create_directories(root / "x" / "a");
  SceneBatchOptions o;
  o.out = (root / "out").string();
  o.ranks = 2;
  o.scenes = {(root / "a").string(), (root / "missing").string()};
  EXPECT_THROW(CheckSceneBatch(o), InputError);  // not a directory
  o.scenes = {(root / "a").string(), (root / "x" / "a").string()};
  EXPECT_THROW(CheckSceneBatch(o), InputError);  // both named a
  o.scenes = {(root / "a").string()};
  o.groups = 3;
  EXPECT_THROW(CheckSceneBatch(o), InputError);  // more groups than ranks
  o.groups = 0;
  o.ranks = 0;
  EXPECT_THROW(CheckSceneBatch(o), InputError);
  o.ranks = 2;
  EXPECT_EQ(CheckSceneBatch(o).groups, 1);  // one scene: one group

  const std::string driver = (kBin / "eulersplat").string();
  std::string log;
  EXPECT_EQ(RunCommand(driver + " --scenes " + (root / "missing").string() +
                           " --out " + (root / "out").string(),
                       &log),
            1);
  EXPECT_THAT(log, HasSubstr("is not a scene directory"));
  log.clear();
  EXPECT_EQ(RunCommand(driver + " --scenes " + (root / "a").string() +
                           " --out " + (root / "out").string() +
                           " --ranks 2 --groups 3",
                       &log),
            1);
  EXPECT_THAT(log, HasSubstr("--groups 3"));
  EXPECT_FALSE(fs::exists(root / "out"));
  fs::remove_all(root);
}

TEST(SceneBatchTest, EachSceneRunsOnItsGroupAndAFailureSparesTheOthers) {
  const fs::path root =
      FreshBuildDir("scene_batch_test_" + std::to_string(::getpid()));
  std::string log;
  for (const char* name : {"lake", "falls"}) {
    ASSERT_EQ(RunCommand((kBin / "es_synth").string() + " --out " +
                             (root / name).string() +
                             " --frames 8 --width 32 --height 24 "
                             "--detail 0.02 --num_points 50",
                         &log),
              0)
        << log;
  }
  fs::create_directories(root / "empty");  // no frames: its run fails
  // A scene list file, as --scenes also takes.
  std::ofstream((root / "scenes.txt").string())
      << (root / "lake").string() << "\n# a comment\n"
      << (root / "empty").string() << "\n"
      << (root / "falls").string() << "\n";
  log.clear();
  const fs::path out = root / "out";
  EXPECT_EQ(RunCommand((kBin / "eulersplat").string() + " --scenes " +
                           (root / "scenes.txt").string() + " --out " +
                           out.string() + " --ranks 2" +
                           kFewIterationsFlags,
                       &log),
            1)
      << log;
  EXPECT_THAT(log,
              HasSubstr("3 scene(s) on 2 rank(s) in 2 group(s) of 1 rank(s)"));
  EXPECT_THAT(log, HasSubstr("[batch] empty: FAILED"));
  EXPECT_THAT(log, HasSubstr("2 of 3 scene(s) done; failed: empty"));
  for (const char* name : {"lake", "falls"}) {
    EXPECT_THAT(log, HasSubstr("[batch] " + std::string(name) + ": done"));
    // Its stage lines, prefixed with its name.
    EXPECT_THAT(log, HasSubstr("[" + std::string(name) + "] stage 1/"));
    EXPECT_TRUE(fs::exists(out / name / "eval" / "eval.json")) << name;
    EXPECT_TRUE(fs::exists(out / (std::string(name) + ".log"))) << name;
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace es
