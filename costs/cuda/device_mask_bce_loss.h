#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_MASK_BCE_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_MASK_BCE_LOSS_H_

// MaskBceLoss (costs/mask_bce_loss.h) on a CUDA device: the mean binary
// cross-entropy of a rendered per-pixel water probability against a mask,
// with the same clamp (kMaskProbabilityMargin), computed in double from
// the rasterizer's float channel. No CUDA types; failures throw CudaError.

#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DeviceMaskBceLoss {
 public:
  // The loss of channel `channel` of `extra` (device, H W num_extra floats:
  // DeviceImages::extra's layout) against `mask` (device, H W floats in
  // [0, 1], 1 = water). If d_extra (device, extra's layout) is not null,
  // its channel `channel` receives scale * dl / d probability and its other
  // channels are left as they are. Only the loss's sum comes back to the
  // host.
  double Evaluate(const float* extra, int num_extra, int channel,
                  const float* mask, int width, int height, double scale,
                  float* d_extra);

 private:
  DeviceBuffer<double> partials_, sum_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_MASK_BCE_LOSS_H_
