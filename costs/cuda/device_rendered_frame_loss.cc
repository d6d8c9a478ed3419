#include "costs/cuda/device_rendered_frame_loss.h"

#include <glog/logging.h>

#include "costs/cuda/splat_cost_kernels.h"

namespace es {
namespace cuda {

DeviceRenderedFrameLoss::DeviceRenderedFrameLoss(const ImageLossTerms& terms)
    : terms_(terms), photometric_(terms.ssim_weight) {}

void DeviceRenderedFrameLoss::SetFrame(const Camera& camera,
                                       const float* image,
                                       const float* mask) {
  CHECK(image != nullptr || terms_.photometric_weight == 0)
      << "the photometric term needs the frame's image";
  CHECK(mask != nullptr || !mask_on())
      << "the mask term needs the frame's mask";
  camera_ = camera;
  image_ = image;
  mask_ = mask;
}

void DeviceRenderedFrameLoss::AttachDynamicChannel(
    const double* dynamic_logits, DeviceSplatView* view) {
  if (!mask_on()) return;
  probability_.Resize(view->count);
  SigmoidArray(view->count, dynamic_logits, probability_.data());
  view->num_extra = 1;
  view->extra = probability_.data();
}

double DeviceRenderedFrameLoss::Score(const DeviceImages& render,
                                      bool want_grad) {
  const int w = camera_.width, h = camera_.height;
  double loss = 0;
  last_photometric_ = last_mask_ = 0;
  have_d_rgb_ = terms_.photometric_weight != 0 && want_grad;
  if (terms_.photometric_weight != 0) {
    d_rgb_.Resize(3 * pixels());
    last_photometric_ = photometric_.Evaluate(
        render.rgb, image_, w, h, terms_.photometric_weight,
        want_grad ? d_rgb_.data() : nullptr);
    loss += terms_.photometric_weight * last_photometric_;
  }
  if (mask_on()) {
    d_extra_.Resize(pixels());
    last_mask_ = mask_loss_.Evaluate(render.extra, 1, 0, mask_, w, h,
                                     terms_.mask_weight,
                                     want_grad ? d_extra_.data() : nullptr);
    loss += terms_.mask_weight * last_mask_;
  }
  return loss;
}

void DeviceRenderedFrameLoss::AddRgbGradient(const float* extra) {
  const long long values = 3LL * camera_.width * camera_.height;
  if (!have_d_rgb_) {  // the photometric term is off
    d_rgb_.Resize(values);
    d_rgb_.Zero();
    have_d_rgb_ = true;
  }
  AddFloatArray(values, extra, d_rgb_.data());
}

DeviceImageGradients DeviceRenderedFrameLoss::ImageGradients() const {
  DeviceImageGradients grads;
  if (have_d_rgb_) grads.d_rgb = d_rgb_.data();
  if (mask_on()) grads.d_extra = d_extra_.data();
  return grads;
}

}  // namespace cuda
}  // namespace es
