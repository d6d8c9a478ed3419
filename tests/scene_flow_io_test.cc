#include "core/flow/scene_flow_io.h"

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "tests/expect_error.h"

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
  samples[1].unseen = Eigen::Vector3d(0.6, 0.0, -0.8);
  samples[2].unseen = Eigen::Vector3d(0.0, 0.5, 0.0);  // a partial weight
  const std::string path = TempPath("es_flow_samples");
  SaveSceneFlowSamples(samples, path);
  const std::vector<SceneFlowSample> read = LoadSceneFlowSamples(path);
  ASSERT_EQ(read.size(), samples.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].x, samples[i].x);
    EXPECT_EQ(read[i].v, samples[i].v);
    EXPECT_EQ(read[i].unseen, samples[i].unseen);
  }
  SaveSceneFlowSamples({}, path);
  EXPECT_TRUE(LoadSceneFlowSamples(path).empty());
  fs::remove(path);
}

TEST(SceneFlowIoTest, ReadsVersionOneFilesWithoutUnseenDirections) {
  const std::string path = TempPath("es_flow_samples_v1");
  {
    std::ofstream out(path, std::ios::binary);
    out << "eulersplat scene flow samples v1\n";
    const int64_t count = 1;
    out.write(reinterpret_cast<const char*>(&count), sizeof(count));
    const double values[6] = {1, 2, 3, 0.1, 0.2, 0.3};
    out.write(reinterpret_cast<const char*>(values), sizeof(values));
  }
  const std::vector<SceneFlowSample> read = LoadSceneFlowSamples(path);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].x, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(read[0].v, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(read[0].unseen, Eigen::Vector3d::Zero());
  fs::remove(path);
}

TEST(SceneFlowIoTest, BadFilesAreInputErrorsNamingThem) {
  const std::string path = TempPath("es_flow_samples_bad");
  std::vector<SceneFlowSample> samples(2);
  SaveSceneFlowSamples(samples, path);
  auto expect_error = [&path](const std::string& what) {
    SCOPED_TRACE(what);
    ExpectErrorNaming<InputError>([&] { LoadSceneFlowSamples(path); }, {path});
  };
  fs::resize_file(path, fs::file_size(path) - 8);
  expect_error("truncated");
  samples[1].v.y() = NAN;
  SaveSceneFlowSamples(samples, path);
  expect_error("non-finite");
  samples[1].v.y() = 0;
  samples[1].unseen = Eigen::Vector3d(0, 2, 0);
  SaveSceneFlowSamples(samples, path);
  expect_error("unseen direction longer than a unit vector");
  std::ofstream(path) << "eulersplat motion field v1\n";
  expect_error("wrong magic");
  fs::remove(path);
  expect_error("missing");
}

}  // namespace
}  // namespace es
