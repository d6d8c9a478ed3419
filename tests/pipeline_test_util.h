#ifndef EULERSPLAT_TESTS_PIPELINE_TEST_UTIL_H_
#define EULERSPLAT_TESTS_PIPELINE_TEST_UTIL_H_

// Helpers for the tests that run the built apps as commands.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <regex>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "tests/whole_file.h"

namespace es {

// Where the build puts the apps.
inline const std::filesystem::path kBin =
    std::filesystem::path(ES_BINARY_DIR) / "bin";

// Passes when every one of `apps` is built; fails naming the first that
// is not.
inline ::testing::AssertionResult AppsBuilt(
    std::initializer_list<const char*> apps) {
  for (const char* app : apps) {
    if (!std::filesystem::exists(kBin / app))
      return ::testing::AssertionFailure()
             << (kBin / app) << " missing: build all targets first";
  }
  return ::testing::AssertionSuccess();
}

// ES_BINARY_DIR/<name>, emptied: a test's own folder in the build.
inline std::filesystem::path FreshBuildDir(const std::string& name) {
  const std::filesystem::path root =
      std::filesystem::path(ES_BINARY_DIR) / name;
  std::filesystem::remove_all(root);
  return root;
}

// eulersplat flags for a run through every stage in a few iterations each.
constexpr char kFewIterationsFlags[] =
    " --cycle_length 4 --static_iterations 4 --flow_iterations 2"
    " --joint_iterations 4 --animate=false";

// Runs a command, returns its exit status and appends its output to *out.
inline int RunCommand(const std::string& command, std::string* out) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return -1;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) {
    out->append(buffer, n);
  }
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A command's exit status (-1 where it did not exit) and its output.
struct CommandResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline CommandResult RunCommand(const std::string& command) {
  CommandResult r;
  r.status = RunCommand(command, &r.output);
  return r;
}

// A fresh folder ES_BINARY_DIR/<name>_<pid> holding a tiny es_synth scene
// (8 frames of 32x24) in scene/; empty path and *log says why on failure.
inline std::filesystem::path MakeTinyDriverScene(const std::string& name,
                                                 std::string* log) {
  const std::filesystem::path root =
      FreshBuildDir(name + "_" + std::to_string(::getpid()));
  if (RunCommand((kBin / "es_synth").string() + " --out " +
                     (root / "scene").string() +
                     " --frames 8 --width 32 --height 24 --detail 0.02"
                     " --num_points 50",
                 log) != 0)
    return {};
  return root;
}

// The number after "key": in a JSON text; NaN when it is null or missing.
inline double JsonNumber(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\": (-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return std::nan("");
  return std::stod(m[1]);
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_PIPELINE_TEST_UTIL_H_
