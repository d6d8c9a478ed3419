#include "costs/water_energy_loss.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>
#include <opencv2/imgproc.hpp>

#include "tests/central_differences.h"
#include "tests/random_rgb_image.h"

namespace es {
namespace {

constexpr int kW = 9, kH = 7;

cv::Mat RandomImage(uint32_t seed) { return RandomRgbImage(kW, kH, seed); }

cv::Mat HalfMask(bool left) {
  cv::Mat m(kH, kW, CV_32FC1, cv::Scalar(0.0));
  m.colRange(left ? 0 : kW / 2, left ? kW / 2 + 1 : kW).setTo(1.0);
  return m;
}

TEST(WaterEnergyLossTest, RenderLikeTheInputScoresZero) {
  const cv::Mat a = RandomImage(1), b = RandomImage(2);
  std::vector<double> ra = FlatRgb(a), rb = FlatRgb(b);
  std::vector<double> da(ra.size(), 0.0), db(rb.size(), 0.0);
  WaterEnergyLoss loss;
  WaterEnergyTerms terms;
  EXPECT_EQ(loss.Evaluate(ra.data(), rb.data(), a, b, HalfMask(true),
                          HalfMask(false), 1.0, da.data(), db.data(), &terms),
            0.0);
  EXPECT_EQ(terms.motion, 0.0);
  EXPECT_EQ(terms.detail, 0.0);
  for (double g : da) EXPECT_EQ(g, 0.0);
}

// A still, flat render against an input that brightens uniformly by c:
// the input's luminance change energy is 3 c^2 everywhere (luminance is
// (R + G + B) / sqrt(3); the window sums to 1, also at the clamped
// borders), its chroma change 0, the render's 0, and neither has texture.
// The motion term is the mean over the three opponent channels.
TEST(WaterEnergyLossTest, StillRenderOfAChangingInputKnownAnswer) {
  const double c = 0.1;
  const cv::Mat a(kH, kW, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3));
  const cv::Mat b(kH, kW, CV_32FC3, cv::Scalar(0.3 + c, 0.3 + c, 0.3 + c));
  std::vector<double> still = FlatRgb(a);
  WaterEnergyOptions options;
  WaterEnergyLoss loss(options);
  WaterEnergyTerms terms;
  loss.Evaluate(still.data(), still.data(), a, b, cv::Mat(), cv::Mat(), 1.0,
                nullptr, nullptr, &terms);
  EXPECT_NEAR(terms.motion,
              (std::sqrt(3 * c * c + options.eps) - std::sqrt(options.eps)) /
                  3,
              1e-6);
  EXPECT_NEAR(terms.detail, 0.0, 1e-12);
  // The render's own change, in the input's amount, closes the gap.
  std::vector<double> moved = FlatRgb(b);
  loss.Evaluate(still.data(), moved.data(), a, b, cv::Mat(), cv::Mat(), 1.0,
                nullptr, nullptr, &terms);
  EXPECT_NEAR(terms.motion, 0.0, 1e-6);
}

// The input brightens by c on every channel; the render's red and blue
// rise by c and its green falls by c: each RGB channel changes by the
// input's amount (a loss per RGB channel scores 0), but the render's
// luminance changes by a third of the input's and its chroma changes,
// which the opponent channels count:
//   motion = (|sqrt(c^2 / 3 + eps) - sqrt(3 c^2 + eps)|
//             + sqrt(2 c^2 + eps) - sqrt(eps)
//             + sqrt(2 c^2 / 3 + eps) - sqrt(eps)) / 3.
TEST(WaterEnergyLossTest, TintedChangeOfTheInputsAmountIsCounted) {
  const double c = 0.1, eps = WaterEnergyOptions().eps;
  const cv::Mat a(kH, kW, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5));
  const cv::Mat b(kH, kW, CV_32FC3, cv::Scalar::all(0.5 + c));
  const cv::Mat tinted(kH, kW, CV_32FC3,
                       cv::Scalar(0.5 + c, 0.5 - c, 0.5 + c));
  const std::vector<double> ra = FlatRgb(a), rb = FlatRgb(tinted);
  WaterEnergyOptions options;
  options.detail_weight = 0;
  WaterEnergyLoss loss(options);
  WaterEnergyTerms terms;
  loss.Evaluate(ra.data(), rb.data(), a, b, cv::Mat(), cv::Mat(), 1.0,
                nullptr, nullptr, &terms);
  const double expected =
      (std::abs(std::sqrt(c * c / 3 + eps) - std::sqrt(3 * c * c + eps)) +
       std::sqrt(2 * c * c + eps) - std::sqrt(eps) +
       std::sqrt(2 * c * c / 3 + eps) - std::sqrt(eps)) /
      3;
  EXPECT_NEAR(terms.motion, expected, 1e-6);
}

// A blurred render of a textured input has less detail energy: the detail
// term is positive and its gradient sharpens (a small step against it
// lowers the loss).
TEST(WaterEnergyLossTest, BlurredRenderIsPushedTowardTheInputsTexture) {
  const cv::Mat a = RandomImage(3), b = RandomImage(4);
  cv::Mat blur_a, blur_b;
  cv::GaussianBlur(a, blur_a, cv::Size(5, 5), 1.5);
  cv::GaussianBlur(b, blur_b, cv::Size(5, 5), 1.5);
  std::vector<double> ra = FlatRgb(blur_a), rb = FlatRgb(blur_b);
  WaterEnergyOptions options;
  options.motion_weight = 0;
  WaterEnergyLoss loss(options);
  std::vector<double> da(ra.size(), 0.0), db(rb.size(), 0.0);
  const double before = loss.Evaluate(ra.data(), rb.data(), a, b, cv::Mat(),
                                      cv::Mat(), 1.0, da.data(), db.data());
  EXPECT_GT(before, 0.05);
  for (size_t i = 0; i < ra.size(); ++i) {
    ra[i] -= 1e-3 * da[i];
    rb[i] -= 1e-3 * db[i];
  }
  EXPECT_LT(loss.Evaluate(ra.data(), rb.data(), a, b, cv::Mat(), cv::Mat(),
                          1.0, nullptr, nullptr),
            before);
}

// Every rendered value of both frames against central differences, for
// each term alone and both, with and without masks.
TEST(WaterEnergyLossTest, GradientMatchesFiniteDifferences) {
  const cv::Mat a = RandomImage(5), b = RandomImage(6);
  for (int setting = 0; setting < 6; ++setting) {
    WaterEnergyOptions options;
    options.motion_weight = setting == 1 ? 0.0 : 0.7;
    options.detail_weight = setting == 0 ? 0.0 : 1.3;
    options.detail_sigma = 0.8;
    options.window_sigma = 1.2;
    options.detail_octaves = setting >= 4 ? 3 : 1; // the pyramid's bands
    if (setting % 2 == 0) options.input_noise = {0.05, 0.02, 0.03};
    const bool masked = setting != 3 && setting != 5;
    const cv::Mat ma = masked ? HalfMask(true) : cv::Mat();
    const cv::Mat mb = masked ? HalfMask(false) : cv::Mat();
    std::vector<double> ra = FlatRgb(RandomImage(7)),
                        rb = FlatRgb(RandomImage(8));
    const double scale = 50.0;  // gradients of order 1
    WaterEnergyLoss loss(options);
    std::vector<double> da(ra.size(), 0.25), db(rb.size(), -0.5);
    loss.Evaluate(ra.data(), rb.data(), a, b, ma, mb, scale, da.data(),
                  db.data());
    for (double& g : da) g -= 0.25;  // added to what was there
    for (double& g : db) g += 0.5;
    auto f = [&]() {
      return loss.Evaluate(ra.data(), rb.data(), a, b, ma, mb, scale,
                           nullptr, nullptr);
    };
    SCOPED_TRACE("setting " + std::to_string(setting));
    central_differences::ExpectGradientsNear(da, f, &ra, "d rendered A");
    central_differences::ExpectGradientsNear(db, f, &rb, "d rendered B");
  }
}

// Texture coarser than the finest band (blobs 16 px across, like a
// fountain's puffs) hardly shows in one band and counts several times
// more in a three-band pyramid; a render with the blobs scores 0 with
// either.
TEST(WaterEnergyLossTest, CoarseBandsSeeTextureTheFinestMisses) {
  const int w = 64, h = 48;
  cv::Mat flat(h, w, CV_32FC3, cv::Scalar(0.4, 0.45, 0.5));
  cv::Mat blobs = flat.clone();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float bump = 0.3f * std::sin(x * 2 * M_PI / 32) *
                         std::sin(y * 2 * M_PI / 32);
      blobs.at<cv::Vec3f>(y, x) += cv::Vec3f(bump, bump, bump);
    }
  }
  const std::vector<double> still = FlatRgb(flat), textured = FlatRgb(blobs);
  auto detail = [&](int octaves, const std::vector<double>& render) {
    WaterEnergyOptions options;
    options.motion_weight = 0;
    options.detail_octaves = octaves;
    WaterEnergyLoss loss(options);
    WaterEnergyTerms terms;
    loss.Evaluate(render.data(), render.data(), blobs, blobs, cv::Mat(),
                  cv::Mat(), 1.0, nullptr, nullptr, &terms);
    return terms.detail;
  };
  EXPECT_EQ(detail(1, textured), 0.0);
  EXPECT_EQ(detail(3, textured), 0.0);
  const double one_band = detail(1, still), three_bands = detail(3, still);
  EXPECT_GT(three_bands, 3 * one_band);
  EXPECT_GT(three_bands, 0.01);
}

// A deliberately wrong gradient (the motion term's sign flipped) fails the
// same check: the test can fail.
TEST(WaterEnergyLossTest, WrongGradientIsCaught) {
  const cv::Mat a = RandomImage(9), b = RandomImage(10);
  std::vector<double> ra = FlatRgb(RandomImage(11)),
                      rb = FlatRgb(RandomImage(12));
  WaterEnergyOptions options;
  options.detail_weight = 0;
  WaterEnergyLoss loss(options);
  std::vector<double> da(ra.size(), 0.0), db(rb.size(), 0.0);
  loss.Evaluate(ra.data(), rb.data(), a, b, cv::Mat(), cv::Mat(), 50.0,
                da.data(), db.data());
  auto f = [&]() {
    return loss.Evaluate(ra.data(), rb.data(), a, b, cv::Mat(), cv::Mat(),
                         50.0, nullptr, nullptr);
  };
  int wrong = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    const double numeric =
        central_differences::NumericDerivative(f, &ra[i]);
    if (std::abs(-da[i] - numeric) > central_differences::kTolerance)
      ++wrong;
  }
  EXPECT_GT(wrong, static_cast<int>(ra.size()) / 2);
}

// From 16384 pixels the three opponent channels run in parallel, each on
// its own scratch: the loss and its gradients must not depend on how many
// threads share them.
TEST(WaterEnergyLossTest, ParallelChannelsGiveTheOneThreadResult) {
  const int w = 160, h = 120;
  cv::Mat a(h, w, CV_32FC3), b(h, w, CV_32FC3), ma(h, w, CV_32FC1),
      mb(h, w, CV_32FC1);
  cv::RNG rng(13);
  for (cv::Mat* m : {&a, &b, &ma, &mb})
    rng.fill(*m, cv::RNG::UNIFORM, 0.0, 1.0);
  std::vector<double> ra = FlatRgb(a), rb = FlatRgb(b);
  for (double& v : ra) v = 1.0 - v;  // a render unlike the input
  auto evaluate = [&](int threads, std::vector<double>* da,
                      std::vector<double>* db) {
    omp_set_num_threads(threads);
    WaterEnergyLoss loss;
    da->assign(ra.size(), 0.0);
    db->assign(rb.size(), 0.0);
    return loss.Evaluate(ra.data(), rb.data(), a, b, ma, mb, 1.0, da->data(),
                         db->data());
  };
  std::vector<double> da1, db1, da3, db3;
  const double one = evaluate(1, &da1, &db1);
  const double three = evaluate(3, &da3, &db3);
  omp_set_num_threads(omp_get_num_procs());
  EXPECT_GT(one, 0);
  EXPECT_EQ(one, three);
  EXPECT_EQ(da1, da3);
  EXPECT_EQ(db1, db3);
}

// noise_gain[k] is the share of white noise's variance that band k keeps:
// the mean squared band of a large noise image, away from the borders.
TEST(WaterEnergyLossTest, NoiseGainIsTheBandsShareOfWhiteNoise) {
  const int w = 256, h = 256;
  const double sigma = 0.1;
  WaterEnergyOptions options;
  options.detail_octaves = 3;
  const WaterEnergyKernels kernels = MakeWaterEnergyKernels(options);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> y(static_cast<size_t>(w) * h), low, band;
  for (double& v : y) v = noise(rng);
  internal::BlurScratch scratch;
  for (int k = 0; k < 3; ++k) {
    internal::Band(y, w, h, k, kernels.detail, &scratch, &low, &band);
    double sum = 0;
    int n = 0;
    for (int r = 32; r < h - 32; ++r)
      for (int c = 32; c < w - 32; ++c, ++n) sum += band[r * w + c] * band[r * w + c];
    SCOPED_TRACE("band " + std::to_string(k));
    EXPECT_NEAR(sum / n, kernels.noise_gain[k] * sigma * sigma,
                0.05 * kernels.noise_gain[k] * sigma * sigma);
  }
  EXPECT_GT(kernels.noise_gain[0], kernels.noise_gain[1]);
}

// Bands (each blur once) is Band of every k, bit for bit.
TEST(WaterEnergyLossTest, BandsIsBandOfEveryOctave) {
  const int w = 37, h = 29;
  WaterEnergyOptions options;
  options.detail_octaves = 3;
  const WaterEnergyKernels kernels = MakeWaterEnergyKernels(options);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> y(static_cast<size_t>(w) * h), low, next, band;
  for (double& v : y) v = u(rng);
  internal::BlurScratch scratch;
  std::vector<std::vector<double>> bands(3);
  internal::Bands(y, w, h, 3, kernels.detail, &scratch, &low, &next,
                  bands.data());
  for (int k = 0; k < 3; ++k) {
    internal::Band(y, w, h, k, kernels.detail, &scratch, &low, &band);
    EXPECT_EQ(bands[k], band) << "band " << k;
  }
}

// Input frames = clean water + new noise each frame. Told the noise, the
// loss prefers the clean render to one that paints noise of its own;
// not told, it asks for the noise.
TEST(WaterEnergyLossTest, KnownInputNoiseIsNotAskedOfTheRender) {
  const int w = 48, h = 40;
  const double sigma = 0.05;
  cv::Mat clean_a = RandomRgbImage(w, h, 21), clean_b = RandomRgbImage(w, h, 22);
  cv::GaussianBlur(clean_a, clean_a, cv::Size(0, 0), 1.5);
  cv::GaussianBlur(clean_b, clean_b, cv::Size(0, 0), 1.5);
  auto noisy = [&](const cv::Mat& clean, int seed) {
    cv::Mat n(h, w, CV_32FC3), out;
    cv::RNG(seed).fill(n, cv::RNG::NORMAL, 0.0, sigma);
    out = clean + n;
    return out;
  };
  const cv::Mat in_a = noisy(clean_a, 1), in_b = noisy(clean_b, 2);
  const std::vector<double> clean_ra = FlatRgb(clean_a),
                            clean_rb = FlatRgb(clean_b),
                            noisy_ra = FlatRgb(noisy(clean_a, 3)),
                            noisy_rb = FlatRgb(noisy(clean_b, 4));
  for (bool told : {true, false}) {
    WaterEnergyOptions options;
    if (told) options.input_noise = {sigma, sigma, sigma};
    WaterEnergyLoss loss(options);
    const double clean = loss.Evaluate(clean_ra.data(), clean_rb.data(), in_a,
                                       in_b, cv::Mat(), cv::Mat(), 1.0,
                                       nullptr, nullptr);
    const double painted = loss.Evaluate(noisy_ra.data(), noisy_rb.data(),
                                         in_a, in_b, cv::Mat(), cv::Mat(),
                                         1.0, nullptr, nullptr);
    SCOPED_TRACE(told ? "told the noise" : "not told");
    if (told) {
      EXPECT_LT(clean, 0.5 * painted);
    } else {
      EXPECT_GT(clean, 2 * painted);
    }
  }
}

// The inputs' energies kept between calls give exactly what computing
// them at each call gives, over several pairs and rounds (frames A of one
// pair are frames B of another, some past the cache's budget); and an
// input copied into a cached input's buffer is not taken for the old one.
TEST(WaterEnergyLossTest, CachedInputEnergiesEqualRecomputedOnes) {
  WaterEnergyOptions options;
  options.detail_octaves = 2;
  WaterEnergyOptions uncached_options = options;
  uncached_options.input_cache_bytes = 0;
  // Room for two pairs' motion and three frames' detail energies.
  options.input_cache_bytes = 2 * 2 * 3 * kW * kH * sizeof(double) * 2;
  WaterEnergyLoss cached(options), uncached(uncached_options);
  std::vector<cv::Mat> frames = {RandomImage(11), RandomImage(12),
                                 RandomImage(13), RandomImage(14)};
  const std::vector<double> render_a = FlatRgb(RandomImage(15)),
                            render_b = FlatRgb(RandomImage(16));
  auto expect_same = [&](const cv::Mat& a, const cv::Mat& b) {
    std::vector<double> da(render_a.size(), 0.0), db = da, ua = da, ub = da;
    const double x =
        cached.Evaluate(render_a.data(), render_b.data(), a, b,
                        HalfMask(true), HalfMask(false), 1.0, da.data(),
                        db.data());
    const double y =
        uncached.Evaluate(render_a.data(), render_b.data(), a, b,
                          HalfMask(true), HalfMask(false), 1.0, ua.data(),
                          ub.data());
    EXPECT_EQ(x, y);
    EXPECT_EQ(da, ua);
    EXPECT_EQ(db, ub);
  };
  for (int round = 0; round < 2; ++round)
    for (size_t f = 0; f + 1 < frames.size(); ++f)
      expect_same(frames[f], frames[f + 1]);
  RandomImage(17).copyTo(frames[0]);  // into frame 0's buffer
  expect_same(frames[0], frames[1]);
}

}  // namespace
}  // namespace es
