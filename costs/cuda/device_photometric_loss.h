#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_PHOTOMETRIC_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_PHOTOMETRIC_LOSS_H_

// PhotometricLoss (costs/photometric_loss.h) on a CUDA device:
//   l = (1 - ssim_weight) L1 + ssim_weight (1 - SSIM)
// of a rendered H x W x 3 float image (DeviceImages::rgb's layout) against
// a target of the same layout, both in device memory, with SSIM in float
// as training runs it (window, constants and zero padding of
// core/metrics/ssim_kernels.h). No CUDA types; failures throw CudaError.

#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DevicePhotometricLoss {
 public:
  explicit DevicePhotometricLoss(double ssim_weight);

  // The loss; if d_rendered (device, H W 3 floats) is not null it receives
  // scale * dl / d rendered. Only the loss's two sums come back to the
  // host.
  double Evaluate(const float* rendered, const float* target, int width,
                  int height, double scale, float* d_rendered);

  // The last Evaluate's terms: mean |x - y| and mean SSIM (1 without SSIM).
  double l1() const { return l1_; }
  double ssim() const { return ssim_; }

 private:
  double ssim_weight_;
  double l1_ = 0, ssim_ = 1;
  DeviceBuffer<float> planes_, scratch_, blurred_;
  DeviceBuffer<double> partials_, sums_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_PHOTOMETRIC_LOSS_H_
