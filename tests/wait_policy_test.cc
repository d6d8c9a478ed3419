// The OpenMP wait policy every app sets for itself (apps/common/
// wait_policy.h): only when the user set none, by starting the program
// once more, never twice.

#include "apps/common/wait_policy.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "tests/pipeline_test_util.h"

using ::testing::HasSubstr;

namespace es {
namespace {

const char* const kVariables[] = {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT",
                                  kWaitPolicyMarker};

std::string Get(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "(unset)";
}

// Each test starts from an environment without the three variables and
// leaves the process' own as it found them.
class WaitPolicyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : kVariables) {
      saved_[name] = Get(name);
      ::unsetenv(name);
    }
  }
  void TearDown() override {
    for (const char* name : kVariables) {
      if (saved_[name] == "(unset)") {
        ::unsetenv(name);
      } else {
        ::setenv(name, saved_[name].c_str(), 1);
      }
    }
  }

  // Runs ApplyWaitPolicy with an exec that records what the new image
  // would see and returns (as a failed exec does).
  int Apply() {
    char arg0[] = "app";
    char* argv[] = {arg0, nullptr};
    int execs = 0;
    ApplyWaitPolicy(argv, [&](char** args) {
      ++execs;
      EXPECT_EQ(args, argv) << "the same arguments";
      seen_spincount_ = Get("GOMP_SPINCOUNT");
      seen_marker_ = Get(kWaitPolicyMarker);
    });
    return execs;
  }

  std::map<std::string, std::string> saved_;
  std::string seen_spincount_, seen_marker_;
};

TEST_F(WaitPolicyTest, NeededOnlyWhenTheUserSetNone) {
  EXPECT_TRUE(WaitPolicyNeeded(nullptr, nullptr, nullptr));
  EXPECT_FALSE(WaitPolicyNeeded("passive", nullptr, nullptr));
  EXPECT_FALSE(WaitPolicyNeeded("active", nullptr, nullptr));
  EXPECT_FALSE(WaitPolicyNeeded(nullptr, "0", nullptr));
  EXPECT_FALSE(WaitPolicyNeeded(nullptr, nullptr, "1"));
}

TEST_F(WaitPolicyTest, StartsAgainOnceWithAShortSpin) {
  EXPECT_EQ(Apply(), 1);
  EXPECT_EQ(seen_spincount_, kSpinCount);
  EXPECT_EQ(seen_marker_, "1");
}

// The new image finds the policy set and goes on; and should the policy
// be lost (a user's wrapper unsetting it), the marker still stops a loop.
TEST_F(WaitPolicyTest, TheNewImageDoesNotStartAgain) {
  ::setenv("GOMP_SPINCOUNT", kSpinCount, 1);
  ::setenv(kWaitPolicyMarker, "1", 1);
  EXPECT_EQ(Apply(), 0);
  ::unsetenv("GOMP_SPINCOUNT");
  EXPECT_EQ(Apply(), 0);
}

TEST_F(WaitPolicyTest, TheUsersPolicyIsKept) {
  ::setenv("OMP_WAIT_POLICY", "active", 1);
  EXPECT_EQ(Apply(), 0);
  EXPECT_EQ(Get("GOMP_SPINCOUNT"), "(unset)");
  ::unsetenv("OMP_WAIT_POLICY");
  ::setenv("GOMP_SPINCOUNT", "300000", 1);
  EXPECT_EQ(Apply(), 0);
  EXPECT_EQ(Get("GOMP_SPINCOUNT"), "300000");
}

// A failed exec leaves the default policy (the variable would mislead the
// stages this process starts) and never tries again.
TEST_F(WaitPolicyTest, AFailedExecGoesOnWithTheDefault) {
  EXPECT_EQ(Apply(), 1);
  EXPECT_EQ(Get("GOMP_SPINCOUNT"), "(unset)");
  EXPECT_EQ(Apply(), 0);
}

TEST_F(WaitPolicyTest, DescriptionSaysWhoSetThePolicy) {
  EXPECT_EQ(WaitPolicyDescription(nullptr, kSpinCount, "1"),
            "OpenMP wait policy: GOMP_SPINCOUNT=10000, set by the app");
  EXPECT_EQ(WaitPolicyDescription(nullptr, "5", nullptr),
            "OpenMP wait policy: GOMP_SPINCOUNT=5, the user's");
  EXPECT_EQ(WaitPolicyDescription("active", nullptr, "1"),
            "OpenMP wait policy: OMP_WAIT_POLICY=active, the user's");
  EXPECT_EQ(WaitPolicyDescription(nullptr, nullptr, "1"),
            "OpenMP wait policy: libgomp's default (long spin)");
}

// Runs an app (es_synth, which stops at once without --out) with `env`
// settings and --v=1; returns what it printed.
std::string RunApp(const std::string& env, int* status) {
  const std::string app =
      (std::filesystem::path(ES_BINARY_DIR) / "bin" / "es_synth").string();
  const std::string command =
      "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u " +
      std::string(kWaitPolicyMarker) + " " + env + " timeout 60 " + app +
      " --v=1";
  const CommandResult r = RunCommand(command);
  *status = r.status;
  return r.output;
}

// A real binary from a clean environment starts again once with the
// policy and then runs (a loop would never get to its error: the timeout
// would end it, status 124); the user's setting is left alone.
TEST(WaitPolicyBinaryTest, AnAppStartsAgainWithThePolicyAndRuns) {
  int status = 0;
  std::string output = RunApp("", &status);
  EXPECT_EQ(status, 1) << output;  // es_synth: --out is required
  EXPECT_THAT(output, HasSubstr("GOMP_SPINCOUNT=10000, set by the app"));
  output = RunApp("GOMP_SPINCOUNT=5", &status);
  EXPECT_EQ(status, 1) << output;
  EXPECT_THAT(output, HasSubstr("GOMP_SPINCOUNT=5, the user's"));
}

}  // namespace
}  // namespace es
