#include "core/metrics/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/central_differences.h"

namespace es {
namespace {

cv::Mat RandomImage(int h, int w, int channels, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cv::Mat m(h, w, CV_MAKETYPE(CV_64F, channels));
  double* p = m.ptr<double>();
  for (size_t i = 0; i < m.total() * channels; ++i) p[i] = u(rng);
  return m;
}

TEST(ImageMetricsTest, SsimOfIdenticalImagesIsOne) {
  const cv::Mat x = RandomImage(20, 24, 3, 1);
  EXPECT_NEAR(Ssim(x, x), 1.0, 1e-12);
  EXPECT_EQ(Psnr(x, x), 100.0);
}

TEST(ImageMetricsTest, SsimDropsWithNoise) {
  const cv::Mat x = RandomImage(20, 24, 3, 1);
  const cv::Mat noise = RandomImage(20, 24, 3, 2) - 0.5;
  const double small = Ssim(x + 0.05 * noise, x);
  const double large = Ssim(x + 0.3 * noise, x);
  EXPECT_LT(small, 1.0);
  EXPECT_LT(large, small);
}

// The zero-padded map at the center equals a hand-computed windowed SSIM.
TEST(ImageMetricsTest, SsimMapMatchesDirectFormulaAtCenter) {
  const cv::Mat x = RandomImage(21, 21, 1, 3);
  const cv::Mat y = RandomImage(21, 21, 1, 4);
  double wsum = 0, mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
  for (int di = -5; di <= 5; ++di) {
    for (int dj = -5; dj <= 5; ++dj) {
      const double w = std::exp(-(di * di + dj * dj) / (2 * 1.5 * 1.5));
      const double a = x.at<double>(10 + di, 10 + dj);
      const double b = y.at<double>(10 + di, 10 + dj);
      wsum += w;
      mx += w * a;
      my += w * b;
      exx += w * a * a;
      eyy += w * b * b;
      exy += w * a * b;
    }
  }
  mx /= wsum, my /= wsum, exx /= wsum, eyy /= wsum, exy /= wsum;
  const double sxx = exx - mx * mx, syy = eyy - my * my, sxy = exy - mx * my;
  const double expected =
      (2 * mx * my + kSsimC1) * (2 * sxy + kSsimC2) /
      ((mx * mx + my * my + kSsimC1) * (sxx + syy + kSsimC2));
  EXPECT_NEAR(SsimMap(x, y).at<double>(10, 10), expected, 1e-12);
}

TEST(ImageMetricsTest, SsimGradientMatchesCentralDifferences) {
  cv::Mat x = RandomImage(20, 24, 3, 5);
  const cv::Mat y = RandomImage(20, 24, 3, 6);
  cv::Mat grad;
  Ssim(x, y, &grad);
  // Probe corners, borders and the interior.
  central_differences::ExpectProbedGradientNear(
      grad.ptr<double>(), x.ptr<double>(),
      {0, 1, 2, 3 * 24 * 10 + 3 * 12 + 1, 3 * 24 * 19 + 3 * 23 + 2,
       3 * 24 * 5 + 0, 3 * 24 * 19, 3 * 24 + 3 * 23},
      [&] { return Ssim(x, y); });
}

TEST(ImageMetricsTest, L1ValueAndGradient) {
  const cv::Mat x = RandomImage(4, 5, 3, 7);
  const cv::Mat y = RandomImage(4, 5, 3, 8);
  cv::Mat grad;
  const double l1 = L1Loss(x, y, &grad);
  const cv::Mat diff = cv::abs(x - y);
  EXPECT_NEAR(l1, cv::sum(diff.reshape(1))[0] / 60.0, 1e-14);
  for (int i = 0; i < 60; ++i) {
    const double d = x.ptr<double>()[i] - y.ptr<double>()[i];
    EXPECT_DOUBLE_EQ(grad.ptr<double>()[i], (d > 0 ? 1.0 : -1.0) / 60.0);
  }
}

TEST(ImageMetricsTest, PsnrOfKnownError) {
  const cv::Mat x(8, 8, CV_64FC3, cv::Scalar::all(0.5));
  const cv::Mat y(8, 8, CV_64FC3, cv::Scalar::all(0.6));
  EXPECT_NEAR(Psnr(x, y), 20.0, 1e-9);  // mse = 0.01
}

TEST(ImageMetricsTest, MaskedMetricsUseOnlyTheRegion) {
  cv::Mat x(8, 8, CV_64FC3, cv::Scalar::all(0.5));
  cv::Mat y = x.clone();
  cv::Mat mask(8, 8, CV_32FC1, cv::Scalar(0.0f));
  mask.rowRange(0, 4).setTo(1.0f);
  y.rowRange(0, 4).setTo(cv::Scalar::all(0.6));  // error only in the mask
  EXPECT_NEAR(MaskedPsnr(x, y, mask), 20.0, 1e-9);
  EXPECT_EQ(MaskedPsnr(x, y, mask, /*invert=*/true), 100.0);
  const cv::Mat empty(8, 8, CV_32FC1, cv::Scalar(0.0f));
  EXPECT_TRUE(std::isnan(MaskedPsnr(x, y, empty)));
  EXPECT_TRUE(std::isnan(MaskedSsim(x, y, empty)));
  EXPECT_LT(MaskedSsim(x, y, mask), MaskedSsim(x, y, mask, true));
}

TEST(ImageMetricsTest, FarFromMaskKeepsOnlyPixelsBeyondTheDistance) {
  cv::Mat mask(9, 21, CV_32FC1, cv::Scalar(0.0f));
  mask.at<float>(4, 10) = 1.0f;  // one water pixel
  const cv::Mat far = FarFromMask(mask, 3.0);
  ASSERT_EQ(far.type(), CV_64FC1);
  for (int i = 0; i < far.rows; ++i) {
    for (int j = 0; j < far.cols; ++j) {
      const double distance = std::hypot(i - 4, j - 10);
      EXPECT_EQ(far.at<double>(i, j), distance > 3.0 ? 1.0 : 0.0)
          << "(" << i << ", " << j << ") at distance " << distance;
    }
  }
  // No water anywhere: all of it is far from the water.
  const cv::Mat dry(9, 21, CV_32FC1, cv::Scalar(0.0f));
  EXPECT_EQ(cv::countNonZero(FarFromMask(dry, 3.0)), 9 * 21);
}

}  // namespace
}  // namespace es
