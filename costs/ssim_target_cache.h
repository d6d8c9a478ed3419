#ifndef EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_
#define EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_

#include <opencv2/core.hpp>

#include <cstddef>
#include <memory>
#include <unordered_map>
#include <vector>

#include "core/metrics/ssim.h"

namespace es {

// The SSIM statistics of the training targets, computed the first time a
// target is scored and kept while they fit in a memory budget (training
// scores every frame many times; its target never changes). Targets past
// the budget are recomputed at each call into one spare slot.
//
// A target is known by its pixel buffer, size and type, and a sample of
// its pixels is compared on every lookup, so a buffer freed and reused for
// another image is not mistaken for the old one. Not thread-safe.
template <typename T>
class SsimTargetCache {
 public:
  explicit SsimTargetCache(size_t budget_bytes) : budget_(budget_bytes) {}

  const SsimTarget<T>& Get(const cv::Mat& target, SsimScratch<T>* scratch);

  size_t cached_targets() const { return entries_.size(); }
  size_t cached_bytes() const { return used_; }

 private:
  struct Entry {
    int rows = 0, cols = 0, type = 0;
    std::vector<unsigned char> sample;
    SsimTarget<T> stats;
  };
  static void Describe(const cv::Mat& target, Entry* entry);
  static bool Matches(const cv::Mat& target, const Entry& entry);

  size_t budget_;
  size_t used_ = 0;
  std::unordered_map<const void*, std::unique_ptr<Entry>> entries_;
  SsimTarget<T> spare_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_
