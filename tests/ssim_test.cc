// The fast SSIM (core/metrics/ssim.h) against a direct evaluation of the
// windowed formula, its gradient against central differences, every
// instruction set against that reference, and the photometric loss's
// target cache against uncached evaluations.

#include "core/metrics/ssim.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/metrics/image_metrics.h"
#include "costs/photometric_loss.h"
#include "costs/ssim_target_cache.h"
#include "tests/central_differences.h"
#include "tests/per_simd_level_test.h"

namespace es {
namespace {

cv::Mat RandomImage(int h, int w, int channels, uint32_t seed, int depth) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cv::Mat m(h, w, CV_MAKETYPE(CV_64F, channels));
  double* p = m.ptr<double>();
  for (size_t i = 0; i < m.total() * channels; ++i) p[i] = u(rng);
  cv::Mat out;
  m.convertTo(out, depth);
  return out;
}

// SSIM per value straight from the definition: 11 x 11 Gaussian window
// (sigma 1.5, normalized over all 121 taps), values outside the image zero.
cv::Mat ReferenceSsimMap(const cv::Mat& x, const cv::Mat& y) {
  const int c = x.channels();
  cv::Mat map(x.size(), CV_MAKETYPE(CV_64F, c));
  double wsum = 0;
  for (int di = -5; di <= 5; ++di)
    for (int dj = -5; dj <= 5; ++dj)
      wsum += std::exp(-(di * di + dj * dj) / (2 * 1.5 * 1.5));
  for (int i = 0; i < x.rows; ++i) {
    for (int j = 0; j < x.cols; ++j) {
      for (int ch = 0; ch < c; ++ch) {
        double mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
        for (int di = -5; di <= 5; ++di) {
          for (int dj = -5; dj <= 5; ++dj) {
            const int r = i + di, q = j + dj;
            if (r < 0 || r >= x.rows || q < 0 || q >= x.cols) continue;
            const double w =
                std::exp(-(di * di + dj * dj) / (2 * 1.5 * 1.5)) / wsum;
            const double a = x.ptr<double>(r)[q * c + ch];
            const double b = y.ptr<double>(r)[q * c + ch];
            mx += w * a, my += w * b;
            exx += w * a * a, eyy += w * b * b, exy += w * a * b;
          }
        }
        const double sxx = exx - mx * mx, syy = eyy - my * my;
        const double sxy = exy - mx * my;
        map.ptr<double>(i)[j * c + ch] =
            (2 * mx * my + kSsimC1) * (2 * sxy + kSsimC2) /
            ((mx * mx + my * my + kSsimC1) * (sxx + syy + kSsimC2));
      }
    }
  }
  return map;
}

double MaxAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a.reshape(1), b.reshape(1), cv::NORM_INF);
}

template <typename T>
double FastSsim(const cv::Mat& x, const cv::Mat& y, SimdLevel level,
                cv::Mat* map, cv::Mat* grad) {
  SsimScratch<T> scratch(level);
  SsimTarget<T> target;
  ComputeSsimTarget(y, &scratch, &target);
  map->create(x.size(), x.type());
  grad->create(x.size(), x.type());
  return SsimAgainstTarget(x.ptr<double>(), target, &scratch, 1.0,
                           grad->ptr<double>(), map->ptr<double>());
}

class SsimLevelTest : public PerSimdLevelTest {};

// Odd sizes (rows shorter than a vector, a remainder after every vector)
// and one large enough for the threaded path.
TEST_P(SsimLevelTest, MapMatchesTheDefinitionInDoubleAndFloat) {
  for (const cv::Size size : {cv::Size(7, 3), cv::Size(23, 17),
                              cv::Size(97, 61)}) {
    for (int channels : {1, 3}) {
      const cv::Mat x = RandomImage(size.height, size.width, channels, 1,
                                    CV_64F);
      cv::Mat y = RandomImage(size.height, size.width, channels, 2, CV_64F);
      y = 0.5 * x + 0.5 * y;  // correlated, as a rendering and its target
      const cv::Mat expected = ReferenceSsimMap(x, y);
      const double mean = cv::mean(expected.reshape(1))[0];
      cv::Mat map, grad;
      const std::string what = std::to_string(size.width) + "x" +
                               std::to_string(size.height) + "x" +
                               std::to_string(channels);
      EXPECT_NEAR(FastSsim<double>(x, y, GetParam(), &map, &grad), mean,
                  1e-12)
          << what;
      EXPECT_LT(MaxAbsDifference(map, expected), 1e-12) << what;
      cv::Mat y_float;
      y.convertTo(y_float, CV_32F);
      EXPECT_NEAR(FastSsim<float>(x, y_float, GetParam(), &map, &grad), mean,
                  1e-5)
          << what;
      EXPECT_LT(MaxAbsDifference(map, expected), 2e-4) << what;
    }
  }
}

TEST_P(SsimLevelTest, GradientMatchesCentralDifferences) {
  cv::Mat x = RandomImage(19, 26, 3, 3, CV_64F);
  const cv::Mat y = RandomImage(19, 26, 3, 4, CV_64F);
  cv::Mat map, grad;
  FastSsim<double>(x, y, GetParam(), &map, &grad);
  const int row = 26 * 3;
  // Corners, borders, a value 5 from the border and the interior.
  central_differences::ExpectProbedGradientNear(
      grad.ptr<double>(), x.ptr<double>(),
      {0, 2, row - 1, 5 * row + 15, 9 * row + 40, 18 * row + 1,
       18 * row + row - 2, 4 * row + 3 * 5 + 1},
      [&] { return cv::mean(ReferenceSsimMap(x, y).reshape(1))[0]; });
}

// Training's float gradient against the double one: same direction, the
// error far below the gradient's own size.
TEST_P(SsimLevelTest, FloatGradientMatchesDouble) {
  const cv::Mat x = RandomImage(61, 97, 3, 5, CV_64F);
  cv::Mat y = RandomImage(61, 97, 3, 6, CV_64F);
  y = 0.7 * x + 0.3 * y;
  cv::Mat map, grad_double, grad_float, y_float;
  FastSsim<double>(x, y, GetParam(), &map, &grad_double);
  y.convertTo(y_float, CV_32F);
  FastSsim<float>(x, y_float, GetParam(), &map, &grad_float);
  const double scale = cv::norm(grad_double, cv::NORM_INF);
  EXPECT_GT(scale, 0);
  EXPECT_LT(MaxAbsDifference(grad_float, grad_double), 1e-3 * scale);
}

INSTANTIATE_TEST_SUITE_P(Levels, SsimLevelTest, AllSimdLevels(),
                         SimdLevelTestName);

// The photometric loss (SSIM and L1 fused into one sweep) equals its terms
// computed apart: 0.8 L1 + 0.2 (1 - SSIM), and its gradient likewise, in
// double to rounding and in float (training) to float tolerance; with no
// SSIM weight, plain L1.
TEST(PhotometricLossTest, EqualsItsTermsInBothPrecisions) {
  const cv::Mat x = RandomImage(37, 53, 3, 13, CV_64F);
  cv::Mat y = RandomImage(37, 53, 3, 14, CV_64F);
  y = 0.6 * x + 0.4 * y;
  cv::Mat d_l1, d_ssim;
  const double l1 = L1Loss(x, y, &d_l1);
  const double ssim = Ssim(x, y, &d_ssim);
  for (double weight : {0.2, 0.0}) {
    const cv::Mat expected_grad = 0.5 * ((1 - weight) * d_l1 - weight * d_ssim);
    const double expected = (1 - weight) * l1 + weight * (1 - ssim);
    const double grad_size = cv::norm(expected_grad, cv::NORM_INF);
    for (bool use_double : {true, false}) {
      cv::Mat target;
      y.convertTo(target, use_double ? CV_64F : CV_32F);
      PhotometricLoss loss(weight, use_double);
      cv::Mat grad(x.size(), x.type());
      const double value =
          loss.Evaluate(x.ptr<double>(), target, 0.5, grad.ptr<double>());
      const std::string what = std::string(use_double ? "double" : "float") +
                               " weight " + std::to_string(weight);
      EXPECT_NEAR(value, expected, use_double ? 1e-12 : 1e-6) << what;
      EXPECT_LT(MaxAbsDifference(grad, expected_grad),
                (use_double ? 1e-12 : 1e-3) * grad_size)
          << what;
    }
  }
}

// Scoring against a cached target gives exactly what recomputing its
// statistics gives, in both precisions, for cached and over-budget targets.
TEST(SsimTargetCacheTest, CachedEqualsUncached) {
  for (bool use_double : {false, true}) {
    const int depth = use_double ? CV_64F : CV_32F;
    const std::vector<cv::Mat> targets = {
        RandomImage(30, 40, 3, 7, depth), RandomImage(30, 40, 3, 8, depth),
        RandomImage(30, 40, 3, 9, depth)};
    const cv::Mat x = RandomImage(30, 40, 3, 10, CV_64F);
    // Room for the first two targets' statistics only.
    const size_t one = 30 * 40 * 3 * (use_double ? 8 : 4) * 2;
    PhotometricLoss cached(0.2, use_double, 2 * one);
    PhotometricLoss uncached(0.2, use_double, 0);
    std::vector<double> d_cached(x.total() * 3), d_uncached(x.total() * 3);
    for (int round = 0; round < 2; ++round) {
      for (const cv::Mat& y : targets) {
        const double a =
            cached.Evaluate(x.ptr<double>(), y, 0.5, d_cached.data());
        const double b =
            uncached.Evaluate(x.ptr<double>(), y, 0.5, d_uncached.data());
        EXPECT_EQ(a, b);
        EXPECT_EQ(d_cached, d_uncached);
      }
    }
  }
}

TEST(SsimTargetCacheTest, KeepsWhatFitsAndNoticesANewImageInABuffer) {
  SsimScratch<float> scratch;
  cv::Mat a = RandomImage(30, 40, 3, 11, CV_32F);
  const cv::Mat b = RandomImage(30, 40, 3, 12, CV_32F);
  const size_t one = 30 * 40 * 3 * sizeof(float) * 2;
  SsimTargetCache<float> cache(one);
  const SsimTarget<float>& first = cache.Get(a, &scratch);
  EXPECT_EQ(&cache.Get(a, &scratch), &first);  // kept, not recomputed
  EXPECT_EQ(cache.cached_targets(), 1u);
  EXPECT_EQ(cache.cached_bytes(), one);
  cache.Get(b, &scratch);  // over the budget: not kept
  EXPECT_EQ(cache.cached_targets(), 1u);

  // Another image copied into a's buffer must not reuse a's statistics.
  b.copyTo(a);
  const SsimTarget<float>& now = cache.Get(a, &scratch);
  SsimTarget<float> fresh;
  ComputeSsimTarget(b, &scratch, &fresh);
  EXPECT_EQ(now.mu, fresh.mu);
  EXPECT_EQ(now.var, fresh.var);
}

}  // namespace
}  // namespace es
