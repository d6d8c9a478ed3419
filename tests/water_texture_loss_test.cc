#include "costs/water_texture_loss.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>
#include <opencv2/imgproc.hpp>

#include "tests/central_differences.h"
#include "tests/random_rgb_image.h"

namespace es {
namespace {

WaterTextureOptions On() {
  WaterTextureOptions options;
  options.weight = 1.0;
  return options;
}

TEST(WaterTextureLossTest, RenderLikeTheInputScoresZero) {
  const cv::Mat input = RandomRgbImage(12, 10, 1);
  std::vector<double> render = FlatRgb(input), grad(render.size(), 0.0);
  WaterTextureLoss loss(On());
  EXPECT_EQ(loss.dims(), 3 * 2 * 9);
  EXPECT_EQ(loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 7,
                          grad.data()),
            0.0);
  for (double g : grad) EXPECT_EQ(g, 0.0);
}

// The distance compares sets, not pixels: a second draw of the same noise
// is far closer to the input than the input blurred (a time-averaged
// sheet of water), although it is the worse per-pixel match.
TEST(WaterTextureLossTest, AnotherDrawIsCloserThanABlur) {
  const int w = 64, h = 64;
  const cv::Mat input = RandomRgbImage(w, h, 2),
                other = RandomRgbImage(w, h, 3);
  cv::Mat blurred;
  cv::GaussianBlur(input, blurred, cv::Size(5, 5), 1.5);
  WaterTextureLoss loss(On());
  const std::vector<double> draw = FlatRgb(other), blur = FlatRgb(blurred);
  const double d_draw =
      loss.Evaluate(draw.data(), input, cv::Mat(), 1.0, 5, nullptr);
  const double d_blur =
      loss.Evaluate(blur.data(), input, cv::Mat(), 1.0, 5, nullptr);
  EXPECT_GT(d_draw, 0.0);
  EXPECT_LT(d_draw, 0.2 * d_blur);
  EXPECT_GT(cv::norm(other, input, cv::NORM_L1),
            cv::norm(blurred, input, cv::NORM_L1));
}

// Only the water counts: a mask with one pixel (or none) gives 0, and a
// render that differs from the input only far from the water (beyond the
// neighbourhoods and the blurs) scores 0.
TEST(WaterTextureLossTest, OnlyTheWaterCounts) {
  const int w = 40, h = 12;
  const cv::Mat input = RandomRgbImage(w, h, 4);
  cv::Mat mask(h, w, CV_32FC1, cv::Scalar(0.0));
  WaterTextureLoss loss(On());
  std::vector<double> other = FlatRgb(RandomRgbImage(w, h, 5));
  EXPECT_EQ(loss.Evaluate(other.data(), input, mask, 1.0, 1, nullptr), 0.0);
  mask.at<float>(3, 3) = 1.0f;
  EXPECT_EQ(loss.Evaluate(other.data(), input, mask, 1.0, 1, nullptr), 0.0);
  mask.colRange(0, 8).setTo(1.0);
  cv::Mat far = input.clone();
  far.colRange(30, w).setTo(cv::Scalar(0.9, 0.1, 0.5));
  const std::vector<double> render = FlatRgb(far);
  EXPECT_EQ(loss.Evaluate(render.data(), input, mask, 1.0, 1, nullptr), 0.0);
  EXPECT_GT(loss.Evaluate(other.data(), input, mask, 1.0, 1, nullptr), 0.0);
}

// `draw` picks the directions: the same draw gives the same value, another
// draw another value.
TEST(WaterTextureLossTest, DrawPicksTheDirections) {
  const cv::Mat input = RandomRgbImage(16, 16, 6);
  const std::vector<double> render = FlatRgb(RandomRgbImage(16, 16, 7));
  WaterTextureLoss loss(On());
  const double a = loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 3,
                                 nullptr);
  EXPECT_EQ(a, loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 3,
                             nullptr));
  EXPECT_NE(a, loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 4,
                             nullptr));
}

// The directions are shared among threads, each writing its own: one
// thread and four give the same value and gradient, bit for bit (a
// resumed run on another machine trains the same).
TEST(WaterTextureLossTest, ThreadsDoNotChangeTheResult) {
  const cv::Mat input = RandomRgbImage(40, 30, 8);
  const std::vector<double> render = FlatRgb(RandomRgbImage(40, 30, 9));
  WaterTextureLoss loss(On());
  const int threads = omp_get_max_threads();
  std::vector<double> one(render.size(), 0.0), four(render.size(), 0.0);
  omp_set_num_threads(1);
  const double a = loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 5,
                                 one.data());
  omp_set_num_threads(4);
  const double b = loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 5,
                                 four.data());
  omp_set_num_threads(threads);
  EXPECT_EQ(a, b);
  EXPECT_EQ(one, four);
}

// Every rendered value against central differences (the loss is piecewise
// linear; a step of 1e-6 changes no rank of these random values), with
// and without a mask, one and three bands, and weight and scale applied;
// the gradient is added to what the buffer held.
TEST(WaterTextureLossTest, GradientMatchesFiniteDifferences) {
  const int w = 9, h = 7;
  const cv::Mat input = RandomRgbImage(w, h, 8);
  cv::Mat half(h, w, CV_32FC1, cv::Scalar(0.0));
  half.colRange(0, 5).setTo(1.0);
  for (int setting = 0; setting < 3; ++setting) {
    WaterTextureOptions options = On();
    options.weight = 1.7;
    options.bands = setting == 2 ? 3 : 1;
    options.sigma = 0.8;
    options.projections = 4;
    // The drawn noise is the same at every evaluation of one draw.
    if (setting == 2) options.input_noise = {0.03, 0.02, 0.01};
    const cv::Mat mask = setting == 1 ? cv::Mat() : half;
    std::vector<double> render = FlatRgb(RandomRgbImage(w, h, 9));
    const double scale = 30.0;  // gradients of order 1
    WaterTextureLoss loss(options);
    std::vector<double> grad(render.size(), 0.25);
    loss.Evaluate(render.data(), input, mask, scale, 11, grad.data());
    for (double& g : grad) g -= 0.25;
    auto f = [&]() {
      return loss.Evaluate(render.data(), input, mask, scale, 11, nullptr);
    };
    SCOPED_TRACE("setting " + std::to_string(setting));
    central_differences::ExpectGradientsNear(grad, f, &render, "d rendered");
  }
}

// Descending the gradient moves a blurred render's texture toward the
// input's.
TEST(WaterTextureLossTest, BlurredRenderIsPushedTowardTheInputsTexture) {
  const int w = 32, h = 32;
  const cv::Mat input = RandomRgbImage(w, h, 10);
  cv::Mat blurred;
  cv::GaussianBlur(input, blurred, cv::Size(5, 5), 1.5);
  std::vector<double> render = FlatRgb(blurred);
  WaterTextureLoss loss(On());
  const double before =
      loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 0, nullptr);
  for (int step = 0; step < 20; ++step) {
    std::vector<double> grad(render.size(), 0.0);
    loss.Evaluate(render.data(), input, cv::Mat(), 1.0, step, grad.data());
    for (size_t i = 0; i < render.size(); ++i) render[i] -= 200.0 * grad[i];
  }
  EXPECT_LT(loss.Evaluate(render.data(), input, cv::Mat(), 1.0, 0, nullptr),
            0.7 * before);
}

// An input of clean water plus noise: told the noise, the loss adds a
// draw of it to the render, so the clean render comes far closer than
// when the loss is not told (then the input's wider spread of band
// values reads as texture the render lacks).
TEST(WaterTextureLossTest, KnownInputNoiseIsNotAskedOfTheRender) {
  const int w = 64, h = 64;
  const double sigma = 0.05;
  cv::Mat clean = RandomRgbImage(w, h, 8), n(h, w, CV_32FC3);
  cv::GaussianBlur(clean, clean, cv::Size(0, 0), 1.5);
  cv::RNG(9).fill(n, cv::RNG::NORMAL, 0.0, sigma);
  const cv::Mat input = clean + n;
  const std::vector<double> render = FlatRgb(clean);
  WaterTextureOptions told = On();
  told.input_noise = {sigma, sigma, sigma};
  WaterTextureLoss with(told), without(On());
  const double d_told =
      with.Evaluate(render.data(), input, cv::Mat(), 1.0, 5, nullptr);
  const double d_not =
      without.Evaluate(render.data(), input, cv::Mat(), 1.0, 5, nullptr);
  EXPECT_LT(d_told, 0.3 * d_not);
}

// The inputs' water pixels, taps and bands kept between calls give
// exactly what computing them at each call gives, over several inputs and
// rounds (some past the cache's budget); another mask or input in a
// cached one's buffer is not taken for the old one.
TEST(WaterTextureLossTest, CachedInputsEqualRecomputedOnes) {
  const int w = 20, h = 16;
  WaterTextureOptions options = On(), uncached_options = On();
  uncached_options.input_cache_bytes = 0;
  options.input_cache_bytes = 2 * (3 * 2 * w * h * sizeof(double) +
                                   w * h * sizeof(int) * (1 + 9 * 2));
  WaterTextureLoss cached(options), uncached(uncached_options);
  std::vector<cv::Mat> inputs = {RandomRgbImage(w, h, 21),
                                 RandomRgbImage(w, h, 22),
                                 RandomRgbImage(w, h, 23)};
  cv::Mat mask(h, w, CV_32FC1, cv::Scalar(1.0));
  mask.colRange(0, w / 3).setTo(0.0);
  const std::vector<double> render = FlatRgb(RandomRgbImage(w, h, 24));
  uint64_t draw = 0;
  auto expect_same = [&](const cv::Mat& input) {
    std::vector<double> a(render.size(), 0.0), b = a;
    const double x =
        cached.Evaluate(render.data(), input, mask, 1.0, draw, a.data());
    const double y =
        uncached.Evaluate(render.data(), input, mask, 1.0, draw++, b.data());
    EXPECT_EQ(x, y);
    EXPECT_EQ(a, b);
  };
  for (int round = 0; round < 2; ++round)
    for (const cv::Mat& input : inputs) expect_same(input);
  // Another mask in the same buffer: water on the left now.
  mask.setTo(0.0);
  mask.colRange(0, 2 * w / 3).setTo(1.0);
  expect_same(inputs[0]);
  RandomRgbImage(w, h, 25).copyTo(inputs[0]);
  expect_same(inputs[0]);
}

}  // namespace
}  // namespace es
