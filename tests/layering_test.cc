// The tree's layers, checked on its own sources: a file includes only its
// own folder's headers or those of the layers below it, and no two files
// include each other, even through others. docs/DESIGN.md states the order.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

namespace fs = std::filesystem;

// Bottom to top. A folder's cuda/ twin belongs to the folder's layer.
const std::vector<std::string> kLayers = {
    "core/base",       "core/metrics",    "core/model",  "core/io",
    "core/render",     "core/fields",     "core/flow",   "core/loop",
    "core/masks",      "core/viz",        "costs",       "solvers/optim",
    "solvers/checkpoint", "solvers/eval", "solvers/train", "solvers/poses",
    "solvers/pipeline", "synth",         "apps/common", "apps"};

// The layer a source path belongs to: the longest listed folder it lies in.
// -1 for paths outside every layer (tests, the build tree).
int LayerOf(const std::string& path) {
  int best = -1;
  size_t best_length = 0;
  for (size_t i = 0; i < kLayers.size(); ++i) {
    const std::string prefix = kLayers[i] + "/";
    if (path.compare(0, prefix.size(), prefix) == 0 &&
        prefix.size() > best_length) {
      best = static_cast<int>(i);
      best_length = prefix.size();
    }
  }
  return best;
}

// A unit is a header with its sources: "core/io/scene" for scene.h and
// scene.cc.
std::string UnitOf(const std::string& path) {
  return path.substr(0, path.find_last_of('.'));
}

using IncludeMap = std::map<std::string, std::vector<std::string>>;

// Every include that points to a higher layer, as "file -> header".
std::vector<std::string> UpwardIncludes(const IncludeMap& includes) {
  std::vector<std::string> found;
  for (const auto& [file, headers] : includes) {
    const int from = LayerOf(file);
    for (const std::string& header : headers) {
      if (LayerOf(header) > from) found.push_back(file + " -> " + header);
    }
  }
  return found;
}

// The units on some cycle of includes (between units, so a .cc including
// a header that includes the .cc's own header counts).
std::set<std::string> UnitsOnCycles(const IncludeMap& includes) {
  std::map<std::string, std::set<std::string>> graph;
  for (const auto& [file, headers] : includes) {
    for (const std::string& header : headers) {
      if (UnitOf(header) != UnitOf(file)) {
        graph[UnitOf(file)].insert(UnitOf(header));
      }
    }
  }
  // A unit is on a cycle when it reaches itself.
  std::set<std::string> on_cycle;
  for (const auto& [start, next] : graph) {
    std::set<std::string> seen;
    std::vector<std::string> stack(next.begin(), next.end());
    while (!stack.empty()) {
      const std::string unit = stack.back();
      stack.pop_back();
      if (unit == start) {
        on_cycle.insert(start);
        break;
      }
      if (!seen.insert(unit).second) continue;
      const auto it = graph.find(unit);
      if (it != graph.end()) {
        stack.insert(stack.end(), it->second.begin(), it->second.end());
      }
    }
  }
  return on_cycle;
}

// The project includes ("dir/.../x.h") of every source under the layers.
IncludeMap ReadProjectIncludes(const fs::path& root) {
  const std::regex include(R"(^\s*#\s*include\s+"([^"]+)\")");
  const std::set<std::string> extensions = {".h", ".cc", ".cu", ".cuh"};
  IncludeMap includes;
  for (const char* top : {"core", "costs", "solvers", "synth", "apps"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      if (!entry.is_regular_file() ||
          extensions.count(entry.path().extension().string()) == 0) {
        continue;
      }
      const std::string file = entry.path().lexically_relative(root).string();
      std::vector<std::string>& headers = includes[file];
      std::ifstream in(entry.path());
      std::string line;
      std::smatch match;
      while (std::getline(in, line)) {
        if (std::regex_search(line, match, include) &&
            LayerOf(match[1].str()) >= 0) {
          headers.push_back(match[1].str());
        }
      }
    }
  }
  return includes;
}

TEST(LayeringTest, NoFileIncludesAHigherLayer) {
  const IncludeMap includes = ReadProjectIncludes(ES_SOURCE_DIR);
  ASSERT_GT(includes.size(), 100u) << "sources not found under "
                                   << ES_SOURCE_DIR;
  const std::vector<std::string> upward = UpwardIncludes(includes);
  std::string list;
  for (const std::string& line : upward) list += "\n  " + line;
  EXPECT_TRUE(upward.empty()) << "includes that go up a layer:" << list;
}

TEST(LayeringTest, NoIncludeCycles) {
  const std::set<std::string> cycles =
      UnitsOnCycles(ReadProjectIncludes(ES_SOURCE_DIR));
  std::string list;
  for (const std::string& unit : cycles) list += "\n  " + unit;
  EXPECT_TRUE(cycles.empty()) << "units that include themselves:" << list;
}

TEST(LayeringTest, EverySourceFolderIsALayer) {
  for (const auto& [file, headers] : ReadProjectIncludes(ES_SOURCE_DIR)) {
    EXPECT_GE(LayerOf(file), 0) << file << " lies in no layer of kLayers";
  }
}

// The checks themselves catch what they are for.
TEST(LayeringTest, ChecksFindAnUpwardIncludeAndACycle) {
  const IncludeMap includes = {
      {"core/model/gaussians.h", {"core/render/rasterizer.h"}},
      {"core/render/rasterizer.h", {"core/model/gaussians.h"}},
      {"core/render/cuda/project.cu", {"core/base/cuda/device_buffer.h"}},
      {"solvers/train/a.cc", {"solvers/train/b.h"}},
      {"solvers/train/b.h", {"solvers/train/a.h"}},
      {"costs/c.cc", {"costs/c.h", "core/loop/euler_chain.h"}}};
  EXPECT_EQ(UpwardIncludes(includes),
            std::vector<std::string>{
                "core/model/gaussians.h -> core/render/rasterizer.h"});
  EXPECT_EQ(UnitsOnCycles(includes),
            (std::set<std::string>{"core/model/gaussians", "core/render/rasterizer",
                                   "solvers/train/a", "solvers/train/b"}));
}

}  // namespace
}  // namespace es
