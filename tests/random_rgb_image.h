#ifndef EULERSPLAT_TESTS_RANDOM_RGB_IMAGE_H_
#define EULERSPLAT_TESTS_RANDOM_RGB_IMAGE_H_

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace es {

// A w x h float RGB image of uniform noise in [0, 1].
inline cv::Mat RandomRgbImage(int w, int h, uint32_t seed) {
  cv::Mat m(h, w, CV_32FC3);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
  return m;
}

// The image's values, row-major and interleaved, as the losses take a
// render.
inline std::vector<double> FlatRgb(const cv::Mat& image) {
  cv::Mat d;
  image.convertTo(d, CV_64FC3);
  return std::vector<double>(d.ptr<double>(),
                             d.ptr<double>() + d.total() * 3);
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_RANDOM_RGB_IMAGE_H_
