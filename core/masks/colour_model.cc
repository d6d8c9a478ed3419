#include "core/masks/colour_model.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/masks/disk.h"

namespace es {
namespace {

constexpr int kPaletteSize = 4;
// Of the region's pixels, the most water-like quarter makes the palette.
constexpr double kPaletteQuantile = 0.75;
// Histogram pixels: every kStride-th (enough for 4096 bins, and fast).
constexpr int kStride = 3;

}  // namespace

int WaterColourModel::Bin(const cv::Vec3f& colour) {
  int bin = 0;
  for (int c = 0; c < 3; ++c)
    bin = bin * kBins +
          std::clamp(static_cast<int>(colour[c] * kBins), 0, kBins - 1);
  return bin;
}

WaterColourModel::WaterColourModel(const std::vector<cv::Mat>& frames,
                                   const std::vector<cv::Mat>& regions,
                                   int inner, int outer) {
  CHECK_EQ(frames.size(), regions.size());
  const int bins = kBins * kBins * kBins;
  std::vector<double> water(bins, 0), scenery(bins, 0);
  std::vector<cv::Mat> insides(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    cv::Mat outside;
    cv::erode(regions[i], insides[i], Disk(inner));
    cv::dilate(regions[i], outside, Disk(outer));
    for (int p = 0; p < static_cast<int>(outside.total()); p += kStride)
      if (outside.at<uchar>(p) == 0)
        scenery[Bin(frames[i].at<cv::Vec3f>(p))] += 1;
  }
  // A bin's probability, with a floor so that an unseen colour is neutral.
  auto log_probability = [](const std::vector<double>& h) {
    double total = 0;
    for (double v : h) total += v;
    std::vector<float> out(h.size());
    for (size_t b = 0; b < h.size(); ++b)
      out[b] = static_cast<float>(std::log(h[b] / std::max(total, 1.0) +
                                           1e-5));
    return out;
  };
  const std::vector<float> log_scenery = log_probability(scenery);
  log_ratio_.assign(bins, 0.f);
  for (int pass = 0; pass < 2; ++pass) {
    std::fill(water.begin(), water.end(), 0);
    for (size_t i = 0; i < frames.size(); ++i)
      for (int p = 0; p < static_cast<int>(insides[i].total());
           p += kStride) {
        if (insides[i].at<uchar>(p) == 0) continue;
        const int b = Bin(frames[i].at<cv::Vec3f>(p));
        if (pass == 0 || log_ratio_[b] > 0) water[b] += 1;
      }
    const std::vector<float> log_water = log_probability(water);
    for (int b = 0; b < bins; ++b)
      log_ratio_[b] = log_water[b] - log_scenery[b];
  }

  // The palette: the region's most water-like colours, clustered.
  std::vector<float> ratios;
  for (size_t i = 0; i < frames.size(); ++i)
    for (int p = 0; p < static_cast<int>(regions[i].total()); p += kStride)
      if (regions[i].at<uchar>(p))
        ratios.push_back(LogRatio(frames[i].at<cv::Vec3f>(p)));
  if (ratios.size() < kPaletteSize) return;
  auto cut = ratios.begin() + static_cast<long>(kPaletteQuantile *
                                                (ratios.size() - 1));
  std::nth_element(ratios.begin(), cut, ratios.end());
  const float threshold = *cut;
  cv::Mat samples(0, 3, CV_32F);
  for (size_t i = 0; i < frames.size(); ++i)
    for (int p = 0; p < static_cast<int>(regions[i].total()); p += kStride) {
      const cv::Vec3f c = frames[i].at<cv::Vec3f>(p);
      if (regions[i].at<uchar>(p) && LogRatio(c) >= threshold)
        samples.push_back(cv::Mat(1, 3, CV_32F, const_cast<float*>(&c[0])));
    }
  if (samples.rows < kPaletteSize) return;
  cv::Mat mean;
  cv::reduce(samples, mean, 0, cv::REDUCE_AVG);
  mean_water_ = {mean.at<float>(0), mean.at<float>(1), mean.at<float>(2)};
  cv::Mat labels, centers;
  cv::theRNG().state = 0x5eed;  // the same palette on every run
  cv::kmeans(samples, kPaletteSize, labels,
             cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT,
                              20, 1e-3),
             3, cv::KMEANS_PP_CENTERS, centers);
  for (int k = 0; k < centers.rows; ++k)
    palette_.emplace_back(centers.at<float>(k, 0), centers.at<float>(k, 1),
                          centers.at<float>(k, 2));
}

float WaterColourModel::LogRatio(const cv::Vec3f& colour) const {
  return log_ratio_[Bin(colour)];
}

cv::Mat WaterColourModel::LogRatio(const cv::Mat& image) const {
  CHECK_EQ(image.type(), CV_32FC3);
  cv::Mat out(image.size(), CV_32FC1);
  for (int p = 0; p < static_cast<int>(image.total()); ++p)
    out.at<float>(p) = LogRatio(image.at<cv::Vec3f>(p));
  return out;
}

}  // namespace es
