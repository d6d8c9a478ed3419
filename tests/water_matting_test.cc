// Water per pixel inside a motion region (MatWater) on frames whose answer
// is known: a curtain of droplets over textured scenery, where a droplet
// covering more than half of a pixel is water in its own frame, a faint
// one and the scenery between droplets are not; and a sheet of textured
// water that hides its scenery in every frame and is water throughout.

#include "core/masks/water_matting.h"
#include "tests/centered_camera.h"

#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace es {
namespace {

constexpr int kWidth = 64, kHeight = 48, kFrames = 12;
const cv::Rect kDroplets(16, 8, 16, 32);  // the curtain of droplets
const cv::Rect kSheet(32, 8, 16, 32);     // opaque water
const cv::Vec3f kWater(0.82f, 0.86f, 0.9f);

struct Clip {
  std::vector<ResidualFrame> frames;
  std::vector<cv::Mat> images, regions;
  std::vector<cv::Mat> strong, faint;  // droplets above / below share 0.5
};

// A still camera (the carried samples are the same pixel), scenery of brown
// noise, 2x2 droplets of the two shares at random places in every frame
// (a share `dense` of the strong ones opaque).
Clip MakeClip(float strong_share = 0.8f, float faint_share = 0.25f,
              float dense = 0.f) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  const Camera camera = CenteredCamera(kWidth, kHeight, 60);
  cv::Mat scenery(kHeight, kWidth, CV_32FC3);
  for (int p = 0; p < static_cast<int>(scenery.total()); ++p) {
    const float v = 0.2f * u(rng);
    scenery.at<cv::Vec3f>(p) = {0.25f + v, 0.2f + v, 0.15f + v};
  }
  Clip clip;
  cv::Mat region(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  region(kDroplets | kSheet).setTo(255);
  for (int t = 0; t < kFrames; ++t) {
    cv::Mat image = scenery.clone();
    cv::Mat strong(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    cv::Mat faint = strong.clone();
    for (int y = kDroplets.y; y < kDroplets.br().y; y += 2)
      for (int x = kDroplets.x; x < kDroplets.br().x; x += 2) {
        const float draw = u(rng);
        const float share = draw < 0.4f * dense ? 1.f
                            : draw < 0.4f       ? strong_share
                            : draw < 0.6f       ? faint_share
                                                : 0.f;
        if (share == 0) continue;
        const cv::Rect cell(x, y, 2, 2);
        (share > 0.5f ? strong : faint)(cell).setTo(255);
        for (int yy = y; yy < y + 2; ++yy)
          for (int xx = x; xx < x + 2; ++xx) {
            cv::Vec3f& c = image.at<cv::Vec3f>(yy, xx);
            c = share * kWater + (1 - share) * c;
          }
      }
    for (int y = kSheet.y; y < kSheet.br().y; ++y)
      for (int x = kSheet.x; x < kSheet.br().x; ++x)
        image.at<cv::Vec3f>(y, x) = kWater * (0.85f + 0.15f * u(rng));
    ResidualFrame f;
    f.camera = camera;
    f.depth = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(1.f));
    f.time_index = t;
    clip.frames.push_back(f);
    clip.images.push_back(image);
    clip.regions.push_back(region.clone());
    clip.strong.push_back(strong);
    clip.faint.push_back(faint);
  }
  return clip;
}

// The fraction of `where` that `mask` calls water.
double Found(const cv::Mat& mask, const cv::Mat& where) {
  const int total = cv::countNonZero(where);
  return total == 0 ? 0 : cv::countNonZero(mask & where) /
                              static_cast<double>(total);
}

TEST(WaterMattingTest, FindsEachFramesDropletsAndNotTheScenery) {
  const Clip clip = MakeClip();
  const std::vector<cv::Mat> masks = MatWater(
      clip.frames, clip.images, clip.regions, WaterMattingOptions());
  ASSERT_EQ(masks.size(), clip.images.size());
  cv::Mat curtain(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  curtain(kDroplets).setTo(255);
  cv::Mat outside = ~clip.regions[0];
  // Away from the region's edge and the sheet (the blur there mixes).
  cv::Mat inner = curtain.clone();
  inner(cv::Rect(kDroplets.br().x - 2, 0, 2, kHeight)).setTo(0);
  for (int t = 0; t < kFrames; ++t) {
    const cv::Mat strong = clip.strong[t] & inner;
    const cv::Mat faint = clip.faint[t] & inner;
    const cv::Mat clear = inner & ~clip.strong[t] & ~clip.faint[t];
    EXPECT_GT(Found(masks[t], strong), 0.9) << "frame " << t;
    EXPECT_LT(Found(masks[t], faint), 0.2) << "frame " << t;
    EXPECT_LT(Found(masks[t], clear), 0.1) << "frame " << t;
    cv::Mat sheet(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
    sheet(kSheet).setTo(255);
    EXPECT_GT(Found(masks[t], sheet), 0.95) << "frame " << t;
    EXPECT_EQ(Found(masks[t], outside), 0) << "frame " << t;
  }
  // The same droplets found in another frame do not count: each frame's
  // mask follows its own droplets.
  EXPECT_LT(Found(masks[0], clip.strong[1] & ~clip.strong[0] &
                                ~clip.faint[0] & inner),
            0.1);
}

// Translucent droplets (one in six of the strong ones opaque): a pixel's
// wettest colour is often a blend, and so is the palette colour nearest
// it; against that blend a droplet of share 0.4 came out at 0.4 / 0.7,
// water. Within a few pixels some frame shows an opaque droplet.
TEST(WaterMattingTest, TranslucentDropletsAreMeasuredAgainstPureWater) {
  const Clip clip = MakeClip(0.7f, 0.4f, 1.f / 6);
  const std::vector<cv::Mat> masks = MatWater(
      clip.frames, clip.images, clip.regions, WaterMattingOptions());
  cv::Mat inner(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  inner(kDroplets).setTo(255);
  inner(cv::Rect(kDroplets.br().x - 2, 0, 2, kHeight)).setTo(0);
  for (int t = 0; t < kFrames; ++t) {
    EXPECT_GT(Found(masks[t], clip.strong[t] & inner), 0.9) << "frame " << t;
    EXPECT_LT(Found(masks[t], clip.faint[t] & inner), 0.2) << "frame " << t;
  }
}

// A fall (water that changes every frame) into a calm pool: the regions
// hold the fall and the pool's middle only (its calm ends move too little
// for them); a patch of the pool's colour elsewhere is scenery.
struct PoolClip {
  std::vector<ResidualFrame> frames;
  std::vector<cv::Mat> images, regions;
  cv::Mat pool, patch;  // CV_8UC1, 255 = inside
};

PoolClip MakePoolClip() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  const cv::Rect fall(24, 2, 16, 22), pool(4, 24, 56, 20);
  const cv::Rect patch(50, 4, 10, 10);  // the pool's colour, not touching it
  const cv::Rect fall_region(22, 2, 20, 22), pool_region(18, 24, 28, 20);
  const cv::Vec3f blue(0.35f, 0.55f, 0.75f);
  PoolClip clip;
  clip.pool = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  clip.pool(pool).setTo(255);
  clip.patch = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  clip.patch(patch).setTo(255);
  cv::Mat scenery(kHeight, kWidth, CV_32FC3);
  for (int p = 0; p < static_cast<int>(scenery.total()); ++p) {
    const float v = 0.2f * u(rng);
    scenery.at<cv::Vec3f>(p) = {0.25f + v, 0.2f + v, 0.15f + v};
  }
  // Still water, still scenery: the same slight texture in every frame.
  for (int p = 0; p < static_cast<int>(scenery.total()); ++p)
    if (clip.pool.at<uchar>(p) || clip.patch.at<uchar>(p))
      scenery.at<cv::Vec3f>(p) = blue * (0.95f + 0.1f * u(rng));
  cv::Mat regions(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  regions(fall_region).setTo(255);
  regions(pool_region).setTo(255);
  for (int t = 0; t < kFrames; ++t) {
    cv::Mat image = scenery.clone();
    for (int y = fall.y; y < fall.br().y; ++y)
      for (int x = fall.x; x < fall.br().x; ++x)
        image.at<cv::Vec3f>(y, x) = kWater * (0.85f + 0.15f * u(rng));
    ResidualFrame f;
    f.camera.width = kWidth;
    f.camera.height = kHeight;
    f.camera.fx = f.camera.fy = 60;
    f.camera.cx = kWidth / 2.0;
    f.camera.cy = kHeight / 2.0;
    f.depth = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(1.f));
    f.time_index = t;
    clip.frames.push_back(f);
    clip.images.push_back(image);
    clip.regions.push_back(regions.clone());
  }
  return clip;
}

TEST(WaterMattingTest, FollowsCalmWaterConnectedToTheRegions) {
  const PoolClip clip = MakePoolClip();
  const std::vector<cv::Mat> masks = MatWater(
      clip.frames, clip.images, clip.regions, WaterMattingOptions());
  WaterMattingOptions near_regions;
  near_regions.calm_water = false;
  const std::vector<cv::Mat> near = MatWater(
      clip.frames, clip.images, clip.regions, near_regions);
  // Away from the pool's edge (the blur there mixes it with the scenery).
  cv::Mat inner;
  cv::erode(clip.pool, inner, cv::Mat(), cv::Point(-1, -1), 2);
  for (int t = 0; t < kFrames; ++t) {
    EXPECT_GT(Found(masks[t], inner), 0.95) << "frame " << t;
    EXPECT_EQ(Found(masks[t], clip.patch), 0) << "frame " << t;
    // Only near the regions without it (the pool's far ends are missed).
    EXPECT_LT(Found(near[t], inner), 0.7) << "frame " << t;
  }
}

}  // namespace
}  // namespace es
