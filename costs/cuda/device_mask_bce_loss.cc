#include "costs/cuda/device_mask_bce_loss.h"

#include <glog/logging.h>

#include "costs/cuda/mean_loss_kernels.h"

namespace es {
namespace cuda {

double DeviceMaskBceLoss::Evaluate(const float* extra, int num_extra,
                                   int channel, const float* mask, int width,
                                   int height, double scale, float* d_extra) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  CHECK_GE(channel, 0);
  CHECK_LT(channel, num_extra);
  const long long n = static_cast<long long>(width) * height;
  // MaskBceMean's scale * inv_n, in the same order.
  const double inv_n = 1.0 / static_cast<double>(n);
  const int blocks = MeanLossBlocks(n);
  partials_.Resize(blocks);
  sum_.Resize(1);
  MaskBceTerms(n, extra, num_extra, channel, mask, scale * inv_n, d_extra,
               partials_.data());
  SumMeanLossPartials(blocks, partials_.data(), sum_.data());
  double sum;
  sum_.Download(&sum);
  return sum * inv_n;
}

}  // namespace cuda
}  // namespace es
