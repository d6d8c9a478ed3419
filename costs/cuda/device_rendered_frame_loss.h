#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_RENDERED_FRAME_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_RENDERED_FRAME_LOSS_H_

// RenderedFrameLoss (costs/rendered_frame_loss.h) on the device: the
// image-space half that DeviceSplatRenderCost and DeviceJointRenderCost
// share,
//   l = w_p * photometric(rgb, image) + w_m * BCE(dynamic channel, mask),
// scored on a device render against the frame's device image and mask,
// keeping the image gradients for DeviceRasterizer::BackwardDevice. No
// CUDA types; reuses its buffers: not thread-safe.

#include <cstddef>

#include "core/base/cuda/device_buffer.h"
#include "core/model/camera.h"
#include "core/render/cuda/device_rasterizer.h"
#include "core/render/cuda/device_splats.h"
#include "costs/cuda/device_mask_bce_loss.h"
#include "costs/cuda/device_photometric_loss.h"
#include "costs/rendered_frame_loss.h"

namespace es {
namespace cuda {

class DeviceRenderedFrameLoss {
 public:
  explicit DeviceRenderedFrameLoss(const ImageLossTerms& terms);

  const ImageLossTerms& terms() const { return terms_; }
  bool mask_on() const { return terms_.mask_weight != 0; }

  // Points the loss at a frame: its camera, its image (device, H W 3
  // floats, RGB in [0, 1]; needed by the photometric term) and its mask
  // (device, H W floats in [0, 1]; needed by the mask term). The arrays
  // must stay alive and unchanged while the loss uses them.
  void SetFrame(const Camera& camera, const float* image, const float* mask);
  const Camera& camera() const { return camera_; }

  // With the mask term on, makes sigmoid(dynamic_logits) (view->count of
  // them, device) the view's one extra channel; otherwise leaves it alone.
  void AttachDynamicChannel(const double* dynamic_logits,
                            DeviceSplatView* view);
  // The last AttachDynamicChannel's probabilities (device).
  const double* probability() const { return probability_.data(); }

  // The weighted loss of `render` (of the frame's camera). With want_grad
  // it keeps d loss / d image for ImageGradients.
  double Score(const DeviceImages& render, bool want_grad);
  // Adds `extra` (device, H W 3 floats) to the kept d loss / d rgb: a loss
  // on the render that this class does not know (e.g. one across frames).
  void AddRgbGradient(const float* extra);
  // BackwardDevice's input for the last Score(want_grad = true).
  DeviceImageGradients ImageGradients() const;

  // The unweighted terms of the last Score (0 for a disabled term).
  double last_photometric() const { return last_photometric_; }
  double last_mask() const { return last_mask_; }

 private:
  size_t pixels() const {
    return static_cast<size_t>(camera_.width) * camera_.height;
  }

  ImageLossTerms terms_;
  Camera camera_;
  const float* image_ = nullptr;
  const float* mask_ = nullptr;
  DevicePhotometricLoss photometric_;
  DeviceMaskBceLoss mask_loss_;
  DeviceBuffer<double> probability_;
  DeviceBuffer<float> d_rgb_, d_extra_;
  // d_rgb_ holds an image gradient: the photometric term's of the last
  // Score(want_grad), or AddRgbGradient's.
  bool have_d_rgb_ = false;
  double last_photometric_ = 0, last_mask_ = 0;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_RENDERED_FRAME_LOSS_H_
