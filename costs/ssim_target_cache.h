#ifndef EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_
#define EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_

#include <opencv2/core.hpp>

#include <cstddef>

#include "core/metrics/ssim.h"
#include "costs/input_cache.h"

namespace es {

// The SSIM statistics of the training targets, kept while they fit in a
// memory budget (costs/input_cache.h). Not thread-safe.
template <typename T>
class SsimTargetCache {
 public:
  explicit SsimTargetCache(size_t budget_bytes) : cache_(budget_bytes) {}

  const SsimTarget<T>& Get(const cv::Mat& target, SsimScratch<T>* scratch);

  size_t cached_targets() const { return cache_.cached_values(); }
  size_t cached_bytes() const { return cache_.cached_bytes(); }

 private:
  InputCache<SsimTarget<T>> cache_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_SSIM_TARGET_CACHE_H_
