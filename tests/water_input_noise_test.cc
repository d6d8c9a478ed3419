#include "costs/water_input_noise.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace es {
namespace {

constexpr int kW = 96, kH = 64;

// A smooth image (a slow ramp) plus white noise of `sigma` per channel.
cv::Mat SmoothPlusNoise(double sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  cv::Mat image(kH, kW, CV_32FC3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c)
        image.at<cv::Vec3f>(y, x)[c] = static_cast<float>(
            0.2 + 0.4 * x / kW + 0.1 * c + 0.2 * y / kH + noise(rng));
  return image;
}

// A pixel-sized checkerboard of contrast 0.5 over columns [x0, x1): the
// finest texture there is (all diagonal detail), which is not noise.
void PaintChecks(cv::Mat* image, int x0, int x1) {
  for (int y = 0; y < kH; ++y)
    for (int x = x0; x < x1; ++x)
      if ((x + y) % 2)
        image->at<cv::Vec3f>(y, x) += cv::Vec3f(0.5f, 0.5f, 0.5f);
}

std::vector<Frame> Frames(double sigma, int n) {
  std::vector<Frame> frames(n);
  for (int i = 0; i < n; ++i) frames[i].image = SmoothPlusNoise(sigma, i);
  return frames;
}

TEST(WaterInputNoiseTest, FindsTheStdOfWhiteNoiseOnEachOpponentChannel) {
  const std::vector<Frame> frames = Frames(0.03, 5);
  const std::array<double, 3> sigma =
      EstimateInputNoise(frames, {0, 1, 2, 3, 4});
  // Independent noise per RGB channel has the same std on every row of
  // an orthonormal basis.
  for (double s : sigma) EXPECT_NEAR(s, 0.03, 0.003);
}

TEST(WaterInputNoiseTest, SmoothFramesHaveNone) {
  const std::vector<Frame> frames = Frames(0.0, 2);
  for (double s : EstimateInputNoise(frames, {0, 1})) EXPECT_LT(s, 1e-3);
}

// Fine texture on an eighth of the frame raises the median a little (it
// moves up the noise's distribution by that share); the water (the mask)
// is skipped however much of the frame it covers.
TEST(WaterInputNoiseTest, FineTextureAndWaterDoNotCountAsNoise) {
  std::vector<Frame> frames = Frames(0.02, 1);
  PaintChecks(&frames[0].image, 0, kW / 8);
  EXPECT_NEAR(EstimateInputNoise(frames, {0})[0], 0.022, 0.003);

  frames = Frames(0.02, 1);
  PaintChecks(&frames[0].image, 0, 3 * kW / 4);  // the water's texture
  frames[0].mask = cv::Mat(kH, kW, CV_32FC1, cv::Scalar(0.0));
  frames[0].mask.colRange(0, 3 * kW / 4).setTo(1.0);
  EXPECT_NEAR(EstimateInputNoise(frames, {0})[0], 0.02, 0.004);
  frames[0].mask.release();  // without the mask, the checks dominate
  EXPECT_GT(EstimateInputNoise(frames, {0})[0], 0.1);
}

TEST(WaterInputNoiseTest, AllWaterGivesNoEstimate) {
  std::vector<Frame> frames = Frames(0.02, 1);
  frames[0].mask = cv::Mat(kH, kW, CV_32FC1, cv::Scalar(1.0));
  for (double s : EstimateInputNoise(frames, {0})) EXPECT_EQ(s, 0.0);
  EXPECT_TRUE(std::isnan(HaarNoiseSigma(cv::Mat(1, 1, CV_64FC1), cv::Mat())));
}

}  // namespace
}  // namespace es
