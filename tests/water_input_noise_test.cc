#include "costs/water_input_noise.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/metrics/realism.h"

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

cv::Mat Channel(const cv::Mat& image) {
  cv::Mat channel;
  cv::extractChannel(image, channel, 0);
  channel.convertTo(channel, CV_64FC1);
  return channel;
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
  // Under one 8-bit grey level (the rounding of any 8-bit frame): none.
  const std::vector<Frame> rounding = Frames(0.0015, 3);
  for (double s : EstimateInputNoise(rounding, {0, 1, 2})) EXPECT_EQ(s, 0.0);
}

// A blurred random texture (std ~0.1, correlated over a few pixels), as
// fine scenery renders, shifted `shift` pixels right.
cv::Mat Texture(int shift) {
  cv::Mat texture(kH, kW + 16, CV_32FC1);
  cv::randn(texture, 0.0, 0.4);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 1.2);
  cv::Mat image;
  cv::cvtColor(texture.colRange(8 - shift, 8 - shift + kW), image,
               cv::COLOR_GRAY2BGR);
  return image + cv::Scalar(0.5, 0.5, 0.5);
}

// Fine texture that stays put over the whole frame: the old single-frame
// estimate read it as noise; the frames' change has none of it.
TEST(WaterInputNoiseTest, FineStaticTextureIsNotNoise) {
  std::vector<Frame> frames = Frames(0.02, 3);
  for (Frame& f : frames) PaintChecks(&f.image, 0, 3 * kW / 4);
  EXPECT_GT(HaarNoiseSigma(Channel(frames[0].image), cv::Mat()), 0.1);
  for (double s : EstimateInputNoise(frames, {0, 1, 2}))
    EXPECT_NEAR(s, 0.02, 0.003);
}

// Texture moving with the camera by a pixel a frame changes every pixel,
// but as much or more at twice the pixel size: no noise. Noise under
// such motion is found only where it outweighs it, and never overstated:
// where the two cannot be told apart, the losses are told of none.
TEST(WaterInputNoiseTest, TextureMovingWithTheCameraIsNotNoise) {
  std::vector<Frame> frames(4);
  for (int i = 0; i < 4; ++i) {
    cv::theRNG().state = 7;  // the same texture, shifted
    frames[i].image = Texture(i);
  }
  for (double s : EstimateInputNoise(frames, {0, 1, 2, 3}))
    EXPECT_LT(s, 0.004);
  std::vector<Frame> noisy = Frames(0.03, 4);
  for (int i = 0; i < 4; ++i) noisy[i].image += frames[i].image;
  for (double s : EstimateInputNoise(noisy, {0, 1, 2, 3}))
    EXPECT_LT(s, 0.033);
}

// The water (the mask, in either frame of a pair) is skipped however
// much of the frame it covers, and its change is not noise.
TEST(WaterInputNoiseTest, WaterIsSkipped) {
  std::vector<Frame> frames = Frames(0.02, 3);
  for (int i = 0; i < 3; ++i) {
    cv::Mat water = frames[i].image.colRange(0, 3 * kW / 4);
    cv::Mat change(water.size(), water.type());
    cv::randu(change, 0.0, 0.5);  // the water's texture, new each frame
    water += change;
    frames[i].mask = cv::Mat(kH, kW, CV_32FC1, cv::Scalar(0.0));
    frames[i].mask.colRange(0, 3 * kW / 4).setTo(1.0);
  }
  EXPECT_NEAR(EstimateInputNoise(frames, {0, 1, 2})[0], 0.02, 0.004);
  for (Frame& f : frames) f.mask.release();  // without it, the water wins
  EXPECT_GT(EstimateInputNoise(frames, {0, 1, 2})[0], 0.05);
}

// Without two frames that follow each other there is no estimate: one
// frame cannot tell noise from texture.
TEST(WaterInputNoiseTest, NeedsConsecutiveFrames) {
  const std::vector<Frame> frames = Frames(0.03, 4);
  for (double s : EstimateInputNoise(frames, {0})) EXPECT_EQ(s, 0.0);
  for (double s : EstimateInputNoise(frames, {0, 2})) EXPECT_EQ(s, 0.0);
  EXPECT_NEAR(EstimateInputNoise(frames, {0, 2, 3})[0], 0.03, 0.005);
}

TEST(WaterInputNoiseTest, AllWaterGivesNoEstimate) {
  std::vector<Frame> frames = Frames(0.02, 2);
  for (Frame& f : frames) f.mask = cv::Mat(kH, kW, CV_32FC1, cv::Scalar(1.0));
  for (double s : EstimateInputNoise(frames, {0, 1})) EXPECT_EQ(s, 0.0);
  EXPECT_TRUE(std::isnan(HaarNoiseSigma(cv::Mat(1, 1, CV_64FC1), cv::Mat())));
}

// A clean render of a noisy input scores far below the input's change;
// with the estimated noise drawn onto it, like the input.
TEST(WaterInputNoiseTest, DrawnNoiseMakesACleanRenderMoveLikeTheInput) {
  std::vector<Frame> input = Frames(0.025, 6);
  std::vector<cv::Mat> real, clean, noisy;
  const std::vector<Frame> smooth = Frames(0.0, 6);
  for (int i = 0; i < 6; ++i) {
    cv::theRNG().state = 7;
    cv::Mat texture = Texture(0);  // fine texture that stays put
    input[i].image += texture;
    real.push_back(input[i].image);
    cv::Mat render;
    cv::Mat(smooth[i].image + texture).convertTo(render, CV_64FC3);
    clean.push_back(render);
    noisy.push_back(render.clone());
  }
  const std::array<double, 3> sigma =
      EstimateInputNoise(input, {0, 1, 2, 3, 4, 5});
  for (int i = 0; i < 6; ++i) DrawInputNoise(sigma, i, &noisy[i]);
  RealismOptions options;
  options.patch_samples = 1024;  // the distances are not checked
  const RealismMetrics before = ComputeRealism(clean, real, {}, options);
  const RealismMetrics after = ComputeRealism(noisy, real, {}, options);
  EXPECT_LT(before.frame.motion_ratio, 0.2);
  EXPECT_NEAR(after.frame.motion_ratio, 1.0, 0.1);
  EXPECT_NEAR(after.frame.detail_ratio, 1.0, 0.1);
  // No noise: the render is left as it is.
  cv::Mat same = clean[0].clone();
  DrawInputNoise({0, 0, 0}, 1, &same);
  EXPECT_EQ(cv::norm(same, clean[0], cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace es
