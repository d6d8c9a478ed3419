#include "core/io/scene_flow_io.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/io/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  return (fs::path(::testing::TempDir()) /
          (name + "_" + std::to_string(getpid()) + ".bin"))
      .string();
}

TEST(SceneFlowIoTest, RoundTripsExactly) {
  std::vector<SceneFlowSample> samples(3);
  for (int i = 0; i < 3; ++i) {
    samples[i].x = Eigen::Vector3d(i, -0.5 * i, 1.0 / 3.0);
    samples[i].v = Eigen::Vector3d(1e-7 * i, 2.5, -i);
  }
  const std::string path = TempPath("es_flow_samples");
  SaveSceneFlowSamples(samples, path);
  const std::vector<SceneFlowSample> read = LoadSceneFlowSamples(path);
  ASSERT_EQ(read.size(), samples.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].x, samples[i].x);
    EXPECT_EQ(read[i].v, samples[i].v);
  }
  SaveSceneFlowSamples({}, path);
  EXPECT_TRUE(LoadSceneFlowSamples(path).empty());
  fs::remove(path);
}

TEST(SceneFlowIoTest, BadFilesAreInputErrorsNamingThem) {
  const std::string path = TempPath("es_flow_samples_bad");
  std::vector<SceneFlowSample> samples(2);
  SaveSceneFlowSamples(samples, path);
  auto expect_error = [&path](const std::string& what) {
    try {
      LoadSceneFlowSamples(path);
      ADD_FAILURE() << what << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << what;
    }
  };
  fs::resize_file(path, fs::file_size(path) - 8);
  expect_error("truncated");
  samples[1].v.y() = NAN;
  SaveSceneFlowSamples(samples, path);
  expect_error("non-finite");
  std::ofstream(path) << "eulersplat motion field v1\n";
  expect_error("wrong magic");
  fs::remove(path);
  expect_error("missing");
}

}  // namespace
}  // namespace es
