#include "costs/water_input_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "costs/water_energy_terms.h"
#include "costs/water_image_filters.h"

namespace es {
namespace {

// The median of v (reordered); v must not be empty.
double Median(std::vector<double>* v) {
  const size_t mid = v->size() / 2;
  std::nth_element(v->begin(), v->begin() + mid, v->end());
  return (*v)[mid];
}

// Noise under one 8-bit grey level: the rounding every 8-bit frame
// carries (about 0.0012 per opponent channel), far under the water's
// detail; the losses are told of none, so clean input trains as without
// the noise term.
constexpr double kNegligibleNoise = 1.0 / 255;

// Median absolute deviation of a zero-mean Gaussian over its std.
constexpr double kMadPerSigma = 0.6744897501960817;

}  // namespace

double HaarNoiseSigma(const cv::Mat& channel, const cv::Mat& skip) {
  CHECK_EQ(channel.type(), CV_64FC1);
  CHECK(skip.empty() || (skip.type() == CV_8UC1 &&
                         skip.size() == channel.size()));
  std::vector<double> details;
  details.reserve(static_cast<size_t>(channel.total() / 4));
  for (int y = 0; y + 1 < channel.rows; y += 2) {
    const double* r0 = channel.ptr<double>(y);
    const double* r1 = channel.ptr<double>(y + 1);
    for (int x = 0; x + 1 < channel.cols; x += 2) {
      if (!skip.empty() &&
          (skip.at<uint8_t>(y, x) || skip.at<uint8_t>(y, x + 1) ||
           skip.at<uint8_t>(y + 1, x) || skip.at<uint8_t>(y + 1, x + 1)))
        continue;
      details.push_back(std::abs(r0[x] - r0[x + 1] - r1[x] + r1[x + 1]) / 2);
    }
  }
  if (details.empty()) return std::numeric_limits<double>::quiet_NaN();
  return Median(&details) / kMadPerSigma;
}

std::array<double, 2> TemporalHaarDetail(const cv::Mat& prev,
                                         const cv::Mat& next,
                                         const cv::Mat& skip) {
  CHECK_EQ(prev.type(), CV_64FC1);
  CHECK(prev.size() == next.size() && prev.type() == next.type());
  const cv::Mat change = (next - prev) / std::sqrt(2.0);
  const cv::Size half(change.cols / 2, change.rows / 2);
  if (half.area() == 0)
    return {HaarNoiseSigma(change, skip),
            std::numeric_limits<double>::quiet_NaN()};
  cv::Mat coarse, coarse_skip;
  cv::resize(change, coarse, half, 0, 0, cv::INTER_AREA);
  if (!skip.empty()) {
    // A coarse block touching a skipped pixel is skipped too.
    cv::resize(skip, coarse_skip, half, 0, 0, cv::INTER_AREA);
    coarse_skip = coarse_skip > 0;
    cv::dilate(coarse_skip, coarse_skip, cv::Mat::ones(3, 3, CV_8UC1));
  }
  return {HaarNoiseSigma(change, skip), HaarNoiseSigma(coarse, coarse_skip)};
}

std::array<double, 3> EstimateInputNoise(const std::vector<Frame>& frames,
                                         const std::vector<int>& indices) {
  // Per channel: single-frame detail, the change's detail at full and at
  // half size, one value per frame or pair.
  std::array<std::vector<double>, 3> single, fine, coarse;
  std::array<cv::Mat, 3> prev_channels;
  cv::Mat prev_skip;
  int prev_index = -2;
  std::vector<double> values;  // one opponent channel of a frame
  for (int index : indices) {
    const Frame& f = frames[index];
    cv::Mat rgb;
    f.image.convertTo(rgb, CV_64FC3);
    cv::Mat skip = cv::Mat::zeros(rgb.size(), CV_8UC1);
    if (!f.mask.empty()) {
      skip = f.mask > 0.5;
      cv::dilate(skip, skip, cv::Mat::ones(3, 3, CV_8UC1));
    }
    const bool follows = index == prev_index + 1 &&
                         prev_channels[0].size() == rgb.size();
    const cv::Mat pair_skip = follows ? (skip | prev_skip) : cv::Mat();
    for (int c = 0; c < 3; ++c) {
      internal::ChannelOf(rgb.ptr<double>(), rgb.total(), c, &values);
      cv::Mat channel = cv::Mat(rgb.rows, rgb.cols, CV_64FC1, values.data())
                            .clone();
      const double alone = HaarNoiseSigma(channel, skip);
      if (std::isfinite(alone)) single[c].push_back(alone);
      if (follows) {
        const std::array<double, 2> t =
            TemporalHaarDetail(prev_channels[c], channel, pair_skip);
        if (std::isfinite(t[0]) && std::isfinite(t[1])) {
          fine[c].push_back(t[0]);
          coarse[c].push_back(t[1]);
        }
      }
      prev_channels[c] = channel;
    }
    prev_skip = skip;
    prev_index = index;
  }
  std::array<double, 3> sigma = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    if (fine[c].empty()) continue;
    const double t1 = Median(&fine[c]), t2 = Median(&coarse[c]);
    const double temporal =
        std::sqrt(std::max(0.0, (t1 * t1 - t2 * t2) * 4 / 3));
    sigma[c] = std::min(temporal, Median(&single[c]));
    if (sigma[c] < kNegligibleNoise) sigma[c] = 0;
  }
  return sigma;
}

void DrawInputNoise(const std::array<double, 3>& sigma, uint64_t seed,
                    cv::Mat* rgb) {
  CHECK_EQ(rgb->type(), CV_64FC3);
  if (!HasInputNoise(sigma)) return;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  double* p = rgb->ptr<double>();  // a clone or a render: continuous
  CHECK(rgb->isContinuous());
  for (size_t i = 0; i < rgb->total(); ++i, p += 3) {
    // The opponent basis is orthonormal: its transpose takes each
    // channel's noise back to RGB with the same std.
    for (int c = 0; c < 3; ++c) {
      const double n = sigma[c] * normal(rng);
      for (int k = 0; k < 3; ++k) p[k] += n * kWaterOpponent[c][k];
    }
  }
}

}  // namespace es
