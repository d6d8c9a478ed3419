#include "costs/ssim_target_cache.h"

#include <glog/logging.h>

#include <cstring>

namespace es {
namespace {

// Pixels compared on every lookup, spread evenly over the image.
constexpr int kSamplePixels = 64;

template <typename Fn>
void ForEachSample(const cv::Mat& image, Fn fn) {
  const size_t pixel_bytes = image.elemSize();
  const size_t pixels = image.total();
  const size_t step = pixels > kSamplePixels ? pixels / kSamplePixels : 1;
  for (size_t i = 0; i < pixels; i += step)
    fn(image.data + i * pixel_bytes, pixel_bytes);
}

}  // namespace

template <typename T>
void SsimTargetCache<T>::Describe(const cv::Mat& target, Entry* entry) {
  entry->rows = target.rows;
  entry->cols = target.cols;
  entry->type = target.type();
  entry->sample.clear();
  ForEachSample(target, [&](const unsigned char* p, size_t bytes) {
    entry->sample.insert(entry->sample.end(), p, p + bytes);
  });
}

template <typename T>
bool SsimTargetCache<T>::Matches(const cv::Mat& target, const Entry& entry) {
  if (target.rows != entry.rows || target.cols != entry.cols ||
      target.type() != entry.type)
    return false;
  size_t offset = 0;
  bool same = true;
  ForEachSample(target, [&](const unsigned char* p, size_t bytes) {
    same = same && offset + bytes <= entry.sample.size() &&
           std::memcmp(p, entry.sample.data() + offset, bytes) == 0;
    offset += bytes;
  });
  return same && offset == entry.sample.size();
}

template <typename T>
const SsimTarget<T>& SsimTargetCache<T>::Get(const cv::Mat& target,
                                             SsimScratch<T>* scratch) {
  CHECK(target.isContinuous());
  auto it = entries_.find(target.data);
  if (it != entries_.end()) {
    Entry& entry = *it->second;
    if (Matches(target, entry)) return entry.stats;
    // Another image now lives in that buffer: forget the old one.
    used_ -= entry.stats.bytes();
    entries_.erase(it);
  }
  // Statistics own mu and var (and a converted copy unless T matches).
  const size_t values = target.total() * target.channels();
  const size_t need =
      values * sizeof(T) * (target.depth() == cv::DataType<T>::depth ? 2 : 3);
  if (used_ + need > budget_) {
    ComputeSsimTarget(target, scratch, &spare_);
    return spare_;
  }
  auto entry = std::make_unique<Entry>();
  Describe(target, entry.get());
  ComputeSsimTarget(target, scratch, &entry->stats);
  used_ += entry->stats.bytes();
  const SsimTarget<T>& stats = entry->stats;
  entries_.emplace(target.data, std::move(entry));
  return stats;
}

template class SsimTargetCache<float>;
template class SsimTargetCache<double>;

}  // namespace es
