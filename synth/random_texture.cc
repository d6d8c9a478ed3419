#include "synth/random_texture.h"

#include <opencv2/imgproc.hpp>

namespace es {

cv::Mat TwoScaleTexture(int width, int height, int channels, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat fine(height, width, CV_32FC(channels));
  cv::Mat coarse(height, width, CV_32FC(channels));
  rng.fill(fine, cv::RNG::UNIFORM, 0.0, 1.0);
  rng.fill(coarse, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 1.5);
  cv::GaussianBlur(coarse, coarse, cv::Size(0, 0), 6.0);
  cv::Mat texture = fine + coarse;
  cv::normalize(texture, texture, 0.0, 1.0, cv::NORM_MINMAX);
  return texture;
}

}  // namespace es
