#include "costs/water_input_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "costs/water_image_filters.h"

namespace es {
namespace {

// The median of v (reordered); v must not be empty.
double Median(std::vector<double>* v) {
  const size_t mid = v->size() / 2;
  std::nth_element(v->begin(), v->begin() + mid, v->end());
  return (*v)[mid];
}

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

std::array<double, 3> EstimateInputNoise(const std::vector<Frame>& frames,
                                         const std::vector<int>& indices) {
  std::array<std::vector<double>, 3> per_frame;
  std::vector<double> values;  // one opponent channel of a frame
  for (int index : indices) {
    const Frame& f = frames[index];
    cv::Mat rgb;
    f.image.convertTo(rgb, CV_64FC3);
    cv::Mat skip;
    if (!f.mask.empty()) {
      skip = f.mask > 0.5;
      cv::dilate(skip, skip, cv::Mat::ones(3, 3, CV_8UC1));
    }
    for (int c = 0; c < 3; ++c) {
      internal::ChannelOf(rgb.ptr<double>(), rgb.total(), c, &values);
      const cv::Mat channel(rgb.rows, rgb.cols, CV_64FC1, values.data());
      const double sigma = HaarNoiseSigma(channel, skip);
      if (std::isfinite(sigma)) per_frame[c].push_back(sigma);
    }
  }
  std::array<double, 3> sigma = {0, 0, 0};
  for (int c = 0; c < 3; ++c)
    if (!per_frame[c].empty()) sigma[c] = Median(&per_frame[c]);
  return sigma;
}

}  // namespace es
