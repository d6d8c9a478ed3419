#include "core/metrics/realism.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "synth/scene.h"

namespace es {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr int kFrames = 12;
constexpr int kFall = 1;  // water pixels per frame

// A random texture with detail at several scales, values around 0.5.
cv::Mat Texture(int rows, int cols, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat sum(rows, cols, CV_32F, cv::Scalar(0.5));
  for (double sigma : {0.7, 1.5, 3.0}) {
    cv::Mat noise(rows, cols, CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    cv::GaussianBlur(noise, noise, cv::Size(0, 0), sigma);
    sum += 0.12 * noise;
  }
  return sum;
}

// A video like a fixed-camera shot of a waterfall: the left half (the
// water mask) is a texture falling kFall pixels per frame, the right half
// a still texture. `seed` picks the textures (same statistics for all).
struct Video {
  std::vector<cv::Mat> frames;  // CV_32FC3
  std::vector<cv::Mat> masks;   // CV_32FC1, 1 = water
};

Video WaterVideo(uint64_t seed) {
  const cv::Mat water = Texture(kHeight + kFall * kFrames, kWidth / 2, seed);
  const cv::Mat still = Texture(kHeight, kWidth / 2, seed + 1000);
  Video v;
  for (int t = 0; t < kFrames; ++t) {
    cv::Mat grey(kHeight, kWidth, CV_32F);
    const int top = kFall * (kFrames - t);  // content moves down
    water.rowRange(top, top + kHeight).copyTo(grey.colRange(0, kWidth / 2));
    still.copyTo(grey.colRange(kWidth / 2, kWidth));
    cv::Mat rgb;
    cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
    v.frames.push_back(rgb);
    cv::Mat mask(kHeight, kWidth, CV_32F, cv::Scalar(0));
    mask.colRange(0, kWidth / 2).setTo(1);
    v.masks.push_back(mask);
  }
  return v;
}

std::vector<cv::Mat> Blurred(const std::vector<cv::Mat>& frames,
                             const cv::Mat& only = cv::Mat()) {
  std::vector<cv::Mat> out;
  for (const cv::Mat& f : frames) {
    cv::Mat b;
    cv::GaussianBlur(f, b, cv::Size(0, 0), 1.5);
    if (!only.empty()) {
      cv::Mat keep = f.clone();
      b.copyTo(keep, only > 0.5f);
      b = keep;
    }
    out.push_back(b);
  }
  return out;
}

// The figures of `rendered` against `real`, from 4096 patches per region
// (of about 17000 positions): enough for the properties tested here, and
// 4x faster than all of them.
RealismMetrics Realism(const std::vector<cv::Mat>& rendered,
                       const std::vector<cv::Mat>& real,
                       const std::vector<cv::Mat>& masks,
                       RealismOptions options = {}) {
  options.patch_samples = 4096;
  return ComputeRealism(rendered, real, masks, options);
}

TEST(RealismTest, IdenticalVideosScoreOneAndDistanceZero) {
  const Video v = WaterVideo(1);
  const RealismMetrics m = Realism(v.frames, v.frames, v.masks);
  for (const RealismRegion* r : {&m.water, &m.static_region, &m.frame}) {
    EXPECT_GT(r->pixels, 0);
    EXPECT_NEAR(r->detail_ratio, 1.0, 1e-12);
    for (double b : r->band_ratio) EXPECT_NEAR(b, 1.0, 1e-12);
    EXPECT_EQ(r->distance_2d, 0.0);
    EXPECT_EQ(r->distance_3d, 0.0);
    EXPECT_GE(r->patches, 1000);
  }
  EXPECT_NEAR(m.water.motion_ratio, 1.0, 1e-12);
  EXPECT_NEAR(m.frame.motion_ratio, 1.0, 1e-12);
  // The still half does not change: no motion to compare.
  EXPECT_EQ(m.static_region.real_motion, 0.0);
  EXPECT_TRUE(std::isnan(m.static_region.motion_ratio));
  EXPECT_GT(m.water.real_motion, 0.01);
}

TEST(RealismTest, OtherSampleOfTheSameWaterIsClose) {
  // A video with other random textures of the same statistics: detail and
  // motion like the real one, a small distance (the distance compares
  // distributions, not pixels).
  const Video real = WaterVideo(1);
  const Video other = WaterVideo(2);
  const RealismMetrics m = Realism(other.frames, real.frames, real.masks);
  EXPECT_NEAR(m.water.detail_ratio, 1.0, 0.15);  // sampling noise only
  EXPECT_NEAR(m.water.motion_ratio, 1.0, 0.15);
  const RealismMetrics blur =
      Realism(Blurred(real.frames), real.frames, real.masks);
  EXPECT_LT(3 * m.water.distance_2d, blur.water.distance_2d);
  EXPECT_LT(3 * m.water.distance_3d, blur.water.distance_3d);
}

TEST(RealismTest, TheSeedDrawsOtherPatchesOfTheSameStatistics) {
  // Another seed samples other patches and directions: the distance of
  // another sample of the water moves by sampling noise only, and
  // identical videos still score 0.
  const Video real = WaterVideo(1);
  const Video other = WaterVideo(2);
  RealismOptions options;
  const RealismRegion first =
      Realism(other.frames, real.frames, real.masks, options).water;
  options.seed = 7;
  const RealismRegion second =
      Realism(other.frames, real.frames, real.masks, options).water;
  EXPECT_NE(first.distance_2d, second.distance_2d);
  EXPECT_NEAR(first.distance_2d, second.distance_2d,
              0.25 * first.distance_2d);
  EXPECT_NEAR(first.distance_3d, second.distance_3d,
              0.25 * first.distance_3d);
  const RealismRegion same =
      Realism(real.frames, real.frames, real.masks, options).water;
  EXPECT_EQ(same.distance_2d, 0.0);
  EXPECT_EQ(same.distance_3d, 0.0);
}

TEST(RealismTest, ARegionWithFewerPositionsThanPatchesUsesEachOnce) {
  // The left half, 11 frames with a next one: 32 x 48 x 11 positions of
  // water, as many static ones. The default asks for more patches than
  // that, so every position is measured once, whatever the seed.
  const Video real = WaterVideo(1);
  const Video other = WaterVideo(2);
  RealismOptions options;
  options.water_margin = 0;  // the mask itself: exactly the left half
  ASSERT_GT(options.patch_samples, 2 * 16896);
  const RealismMetrics m =
      ComputeRealism(other.frames, real.frames, real.masks, options);
  EXPECT_EQ(m.water.patches, 16896);
  EXPECT_EQ(m.static_region.patches, 16896);
  EXPECT_EQ(m.frame.patches, 2 * 16896);
  options.patch_samples = 16896;  // exactly the region: still all of it
  EXPECT_EQ(ComputeRealism(other.frames, real.frames, real.masks, options)
                .water.distance_2d,
            m.water.distance_2d);
}

TEST(RealismTest, BlurLowersDetailAndRaisesDistance) {
  const Video v = WaterVideo(1);
  const RealismMetrics m =
      Realism(Blurred(v.frames), v.frames, v.masks);
  EXPECT_LT(m.water.detail_ratio, 0.6);
  EXPECT_LT(m.water.band_ratio[0], m.water.band_ratio[2]);  // finest most
  EXPECT_LT(m.water.band_ratio[0], 0.3);
  EXPECT_GT(m.water.distance_2d, 0.01);
  EXPECT_GT(m.water.distance_3d, 0.01);
  EXPECT_LT(m.water.motion_ratio, 1.0);  // blurred changes are smaller
}

TEST(RealismTest, BlurOnlyInTheWaterLeavesTheStaticControlAlone) {
  const Video v = WaterVideo(1);
  const RealismMetrics m =
      Realism(Blurred(v.frames, v.masks[0]), v.frames, v.masks);
  EXPECT_LT(m.water.detail_ratio, 0.6);
  // Only the pixels next to the boundary see the blurred side.
  EXPECT_GT(m.static_region.detail_ratio, 0.9);
  EXPECT_LT(m.static_region.distance_2d, 0.2 * m.water.distance_2d);
}

TEST(RealismTest, FrozenVideoHasNoMotion) {
  const Video v = WaterVideo(1);
  const std::vector<cv::Mat> frozen(kFrames, v.frames[0]);
  const RealismMetrics m = Realism(frozen, v.frames, v.masks);
  EXPECT_EQ(m.water.motion_ratio, 0.0);
  EXPECT_NEAR(m.water.detail_ratio, 1.0, 0.1);  // each frame looks right
  EXPECT_GT(m.water.distance_3d, 3 * m.water.distance_2d);
}

TEST(RealismTest, ShuffledTimeKeepsDetailButNotSpatioTemporalStatistics) {
  const Video v = WaterVideo(1);
  std::vector<int> order(kFrames);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  std::vector<cv::Mat> shuffled;
  for (int t : order) shuffled.push_back(v.frames[t]);
  const RealismMetrics m = Realism(shuffled, v.frames, v.masks);
  EXPECT_NEAR(m.water.detail_ratio, 1.0, 1e-6);  // the same frames
  EXPECT_GT(m.water.motion_ratio, 1.3);  // jumps instead of a steady fall
  EXPECT_GT(m.water.distance_3d, 3 * m.water.distance_2d);
  const RealismMetrics other =
      Realism(WaterVideo(2).frames, v.frames, v.masks);
  EXPECT_GT(m.water.distance_3d, 3 * other.water.distance_3d);
}

TEST(RealismTest, WithoutMasksOnlyTheWholeFrameIsMeasured) {
  const Video v = WaterVideo(1);
  const RealismMetrics m = Realism(Blurred(v.frames), v.frames, {});
  EXPECT_EQ(m.water.pixels, 0);
  EXPECT_TRUE(std::isnan(m.water.detail_ratio));
  EXPECT_TRUE(std::isnan(m.static_region.distance_2d));
  EXPECT_EQ(m.frame.pixels, static_cast<long long>(kWidth) * kHeight *
                                kFrames);
  EXPECT_LT(m.frame.detail_ratio, 0.6);
}

// The synthetic droplet preset drawn with the given water seed: the same
// scenery and cameras, another realization of the spray.
SynthScene Spray(uint64_t water_seed) {
  SynthSettings s;
  s.preset = "droplets";
  s.frames = 8;
  s.width = 80;
  s.height = 60;
  s.detail = 0.15;
  s.num_points = 100;
  s.water_seed = water_seed;
  return GenerateSynthScene(s);
}

TEST(RealismTest, WaterMarginRemovesTheMasksBiasOnSpray) {
  // Another draw of the same spray is as real as the input. Inside the
  // input's own droplet masks it is not: there the input always shows its
  // droplets and the other draw mostly does not, so its motion and
  // distance are off. The region around the droplets compares both fairly.
  const SynthScene real = Spray(1), other = Spray(2);
  RealismOptions mask_only;
  mask_only.water_margin = 0;
  const RealismMetrics biased =
      Realism(other.images, real.images, real.masks, mask_only);
  const RealismMetrics fair =  // the default margin
      Realism(other.images, real.images, real.masks);
  EXPECT_GT(biased.water.motion_ratio, 1.3);
  EXPECT_NEAR(fair.water.motion_ratio, 1.0, 0.1);
  EXPECT_NEAR(fair.water.detail_ratio, 1.0, 0.1);
  EXPECT_LT(3 * fair.water.distance_2d, biased.water.distance_2d);
  // The margin moves pixels from the static region to the water.
  EXPECT_GT(fair.water.pixels, biased.water.pixels);
  EXPECT_EQ(fair.water.pixels + fair.static_region.pixels,
            biased.water.pixels + biased.static_region.pixels);
}

TEST(RealismTest, EightBitAndFloatFramesAgree) {
  const Video v = WaterVideo(1);
  std::vector<cv::Mat> bytes;
  for (const cv::Mat& f : v.frames) {
    cv::Mat b;
    f.convertTo(b, CV_8U, 255);
    bytes.push_back(b);
  }
  const RealismMetrics m = Realism(bytes, v.frames, v.masks);
  EXPECT_NEAR(m.water.detail_ratio, 1.0, 0.02);  // quantization only
  EXPECT_NEAR(m.water.motion_ratio, 1.0, 0.02);
}

}  // namespace
}  // namespace es
