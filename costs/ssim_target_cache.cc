#include "costs/ssim_target_cache.h"

namespace es {

template <typename T>
const SsimTarget<T>& SsimTargetCache<T>::Get(const cv::Mat& target,
                                             SsimScratch<T>* scratch) {
  // Statistics own mu and var (and a converted copy unless T matches).
  const size_t values = target.total() * target.channels();
  const size_t bytes =
      values * sizeof(T) * (target.depth() == cv::DataType<T>::depth ? 2 : 3);
  return cache_.Get({&target}, bytes, [&](SsimTarget<T>* stats) {
    ComputeSsimTarget(target, scratch, stats);
  });
}

template class SsimTargetCache<float>;
template class SsimTargetCache<double>;

}  // namespace es
