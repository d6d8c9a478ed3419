// Poses found on scaled-down frames, expressed at full size: a point must
// project to the same place (scaled) before and after rescaling, and the
// mean reprojection error weights points by their track length.

#include "solvers/poses/colmap_poses.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "core/io/undistort.h"

namespace es {
namespace {

TEST(ColmapPosesTest, RescaledModelProjectsToScaledPixels) {
  ColmapModel model;
  model.cameras[1] = {1, "PINHOLE", 160, 120, {150, 152, 80.5, 59.5}};
  model.cameras[2] = {2, "SIMPLE_RADIAL", 160, 120, {151, 79, 61, 0.02}};
  ColmapImage image;
  image.id = 3;
  image.camera_id = 1;
  image.points2d = {{10, 20}, {100.5, 7.25}};
  model.images[3] = image;
  ColmapPoint3D point;
  point.error = 0.5;
  point.track = {{3, 0}, {3, 1}};
  model.points.push_back(point);

  const double sx = 0.5, sy = 0.5;
  const ColmapModel small = model;
  RescaleColmapModel(sx, sy, 320, 240, &model);
  const std::vector<double>& p = model.cameras[1].params;
  EXPECT_EQ(model.cameras[1].width, 320);
  EXPECT_EQ(model.cameras[1].height, 240);
  // A camera-space point lands at twice the coordinates (COLMAP measures
  // pixels from the image corner, so scaling is exact).
  const Eigen::Vector3d x(0.3, -0.2, 2.0);
  const std::vector<double>& q = small.cameras.at(1).params;
  EXPECT_NEAR(p[0] * x.x() / x.z() + p[2],
              (q[0] * x.x() / x.z() + q[2]) / sx, 1e-9);
  EXPECT_NEAR(p[1] * x.y() / x.z() + p[3],
              (q[1] * x.y() / x.z() + q[3]) / sy, 1e-9);
  const std::vector<double>& r = model.cameras[2].params;
  EXPECT_EQ(r, (std::vector<double>{302, 158, 122, 0.02}));
  EXPECT_EQ(model.images[3].points2d[1], Eigen::Vector2d(201, 14.5));
  EXPECT_EQ(model.points[0].error, 1.0);

  ColmapModel opencv;
  opencv.cameras[1] = {1, "OPENCV", 10, 10, {1, 1, 5, 5, 0, 0, 0, 0}};
  EXPECT_THROW(RescaleColmapModel(0.5, 0.5, 20, 20, &opencv), InputError);
}

TEST(ColmapPosesTest, MeanReprojectionErrorOverObservations) {
  ColmapModel model;
  EXPECT_EQ(MeanReprojectionError(model), 0.0);
  ColmapPoint3D a, b;
  a.error = 1.0;
  a.track = {{1, 0}, {2, 0}, {3, 0}};
  b.error = 3.0;
  b.track = {{1, 1}};
  model.points = {a, b};
  EXPECT_DOUBLE_EQ(MeanReprojectionError(model), (3 * 1.0 + 3.0) / 4);
}

TEST(ColmapPosesTest, VideoMatchPairsAreNeighboursAndPowersOfTwo) {
  using Pairs = std::vector<std::pair<int, int>>;
  // overlap 2 in 10 frames: 1 and 2 apart, then 4 and 8 apart.
  const Pairs pairs = VideoMatchPairs(10, 2);
  EXPECT_EQ(Pairs(pairs.begin(), pairs.begin() + 4),
            (Pairs{{0, 1}, {0, 2}, {0, 4}, {0, 8}}));
  EXPECT_EQ(pairs.back(), std::make_pair(8, 9));
  // Frame 9 is last: it pairs with nothing after it, and nothing twice.
  EXPECT_EQ(std::count(pairs.begin(), pairs.end(), std::make_pair(1, 9)),
            1);
  EXPECT_EQ(std::count(pairs.begin(), pairs.end(), std::make_pair(1, 5)),
            1);
  // 9 + 8 neighbours, and 6 + 2 + ... pairs 4 and 8 apart (6 + 2).
  EXPECT_EQ(pairs.size(), 9u + 8u + 6u + 2u);
  for (const auto& [a, b] : pairs) {
    EXPECT_LT(a, b);
    EXPECT_LT(b, 10);
  }
  // A long video costs about overlap + log2(frames) pairs per frame.
  EXPECT_LT(VideoMatchPairs(1000, 5).size(), 1000u * (5 + 8));
  EXPECT_TRUE(VideoMatchPairs(1, 5).empty());
}

}  // namespace
}  // namespace es
