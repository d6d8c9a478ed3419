#include "costs/input_cache.h"

#include <cstring>

#include <glog/logging.h>

namespace es {
namespace {

// Pixels compared on every lookup, spread evenly over the image.
constexpr int kSamplePixels = 64;

template <typename Fn>
void ForEachSample(const cv::Mat& image, Fn fn) {
  CHECK(image.empty() || image.isContinuous());
  const size_t pixel_bytes = image.elemSize();
  const size_t pixels = image.total();
  const size_t step = pixels > kSamplePixels ? pixels / kSamplePixels : 1;
  for (size_t i = 0; i < pixels; i += step)
    fn(image.data + i * pixel_bytes, pixel_bytes);
}

}  // namespace

InputDescription DescribeInput(const cv::Mat& image) {
  InputDescription d;
  d.rows = image.rows;
  d.cols = image.cols;
  d.type = image.type();
  ForEachSample(image, [&](const unsigned char* p, size_t bytes) {
    d.sample.insert(d.sample.end(), p, p + bytes);
  });
  return d;
}

bool InputMatches(const cv::Mat& image, const InputDescription& described) {
  if (image.rows != described.rows || image.cols != described.cols ||
      image.type() != described.type)
    return false;
  size_t offset = 0;
  bool same = true;
  ForEachSample(image, [&](const unsigned char* p, size_t bytes) {
    same = same && offset + bytes <= described.sample.size() &&
           std::memcmp(p, described.sample.data() + offset, bytes) == 0;
    offset += bytes;
  });
  return same && offset == described.sample.size();
}

}  // namespace es
