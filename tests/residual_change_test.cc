// The residual change on a known answer: a camera slides along a wall; the
// residual against a static model is a fixed pattern on the wall (scenery
// the model has not learned) except in a patch where it is new noise in
// every frame (water). The change must be near zero on the wall and large
// in the patch, and unknown where no partner frame sees the point.

#include "core/masks/residual_change.h"
#include "tests/centered_camera.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace es {
namespace {

constexpr int kWidth = 64, kHeight = 48, kFrames = 30;
constexpr double kWallDepth = 2.0;
constexpr double kStep = 0.02;  // camera slide per frame (0.6 px)

Camera SlidCamera(int i) {
  Camera c = CenteredCamera(kWidth, kHeight, 60);
  c.t_cw = Eigen::Vector3d(-kStep * i, 0, 0);  // center at (kStep i, 0, 0)
  return c;
}

// The wall point (x, y) that pixel (u, v) of frame i sees.
Eigen::Vector2d WallPoint(int i, int u, int v) {
  const Camera c = SlidCamera(i);
  return {(u + 0.5 - c.cx) / c.fx * kWallDepth + kStep * i,
          (v + 0.5 - c.cy) / c.fy * kWallDepth};
}

bool InWater(const Eigen::Vector2d& p) {
  return p.x() > -0.3 && p.x() < 0.3 && p.y() > -0.25 && p.y() < 0.25;
}

std::vector<ResidualFrame> SlidingWall() {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> noise(-0.3f, 0.3f);
  std::vector<ResidualFrame> frames(kFrames);
  for (int i = 0; i < kFrames; ++i) {
    ResidualFrame& f = frames[i];
    f.camera = SlidCamera(i);
    f.time_index = i;
    f.depth = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(kWallDepth));
    f.residual = cv::Mat(kHeight, kWidth, CV_32FC3);
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        const Eigen::Vector2d p = WallPoint(i, u, v);
        // A smooth misfit of up to 0.2, fixed on the wall.
        const float misfit = static_cast<float>(
            0.2 * std::sin(3 * p.x()) * std::cos(4 * p.y()));
        f.residual.at<cv::Vec3f>(v, u) =
            InWater(p) ? cv::Vec3f(noise(random), noise(random),
                                   noise(random))
                       : cv::Vec3f(misfit, -misfit, 0.5f * misfit);
      }
  }
  return frames;
}

TEST(ResidualChangeTest, FixedMisfitCancelsChangingWaterDoesNot) {
  const std::vector<ResidualFrame> frames = SlidingWall();
  const std::vector<cv::Mat> change =
      ResidualChange(frames, ResidualChangeOptions());
  ASSERT_EQ(change.size(), frames.size());
  double wall_sum = 0, water_sum = 0, wall_max = 0;
  int wall_count = 0, water_count = 0;
  for (int i = 0; i < kFrames; ++i)
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        const float c = change[i].at<float>(v, u);
        if (c < 0) continue;
        const Eigen::Vector2d p = WallPoint(i, u, v);
        // Partners sample the patch's edge a pixel or two off: skip it.
        const Eigen::Vector2d margin(0.08, 0.08);
        if (InWater(p)) {
          if (InWater(p - margin) && InWater(p + margin)) {
            water_sum += c;
            ++water_count;
          }
        } else if (!InWater(p - margin) && !InWater(p + margin) &&
                   !InWater(p + Eigen::Vector2d(0.08, -0.08)) &&
                   !InWater(p + Eigen::Vector2d(-0.08, 0.08))) {
          wall_sum += c;
          wall_max = std::max<double>(wall_max, c);
          ++wall_count;
        }
      }
  ASSERT_GT(wall_count, 1000);
  ASSERT_GT(water_count, 1000);
  // The misfit (up to 0.2) cancels to interpolation error.
  EXPECT_LT(wall_sum / wall_count, 0.003);
  EXPECT_LT(wall_max, 0.02);
  // Two uniform noises in [-0.3, 0.3]: mean |difference| 0.2 per channel.
  EXPECT_GT(water_sum / water_count, 0.12);
}

TEST(ResidualChangeTest, UnknownWithoutEnoughPartners) {
  std::vector<ResidualFrame> frames = SlidingWall();
  // No depth in one frame's left half: nothing to carry there.
  frames[10].depth(cv::Rect(0, 0, kWidth / 2, kHeight)).setTo(0);
  ResidualChangeOptions options;
  const std::vector<cv::Mat> change = ResidualChange(frames, options);
  EXPECT_EQ(change[10].at<float>(20, 5), -1.f);
  EXPECT_GE(change[10].at<float>(20, kWidth - 5), 0.f);

  // A frame alone in time has no partners at all.
  ResidualFrame alone = frames[0];
  alone.time_index = 1000;
  frames.push_back(alone);
  const std::vector<cv::Mat> with_alone = ResidualChange(frames, options);
  EXPECT_EQ(cv::countNonZero(with_alone.back() >= 0), 0);

  // The camera slides right, so the left edge of the first frame is seen by
  // no later frame (only by time_index + gap k, all to the right).
  EXPECT_EQ(with_alone[0].at<float>(20, 0), -1.f);
  EXPECT_GE(with_alone[0].at<float>(20, kWidth - 1 - 30), 0.f);
}

}  // namespace
}  // namespace es
