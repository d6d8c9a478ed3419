#include "costs/rendered_frame_loss.h"

#include <glog/logging.h>

#include <algorithm>

#include "core/model/gaussians.h"
#include "costs/mask_bce_loss.h"

namespace es {

ImageLossTerms PhotometricOnlyTerms(double ssim_weight) {
  ImageLossTerms terms;
  terms.photometric_weight = 1.0;
  terms.ssim_weight = ssim_weight;
  terms.mask_weight = 0.0;
  return terms;
}

ImageLossTerms MaskOnlyTerms() {
  ImageLossTerms terms;
  terms.photometric_weight = 0.0;
  terms.mask_weight = 1.0;
  return terms;
}

RenderedFrameLoss::RenderedFrameLoss(const ImageLossTerms& terms,
                                     const RenderOptions& options)
    : terms_(terms),
      photometric_(terms.ssim_weight, options.use_double,
                   terms.ssim_cache_bytes, options.simd) {}

void RenderedFrameLoss::CheckFrame(const Frame& frame) const {
  CHECK_EQ(frame.image.rows, frame.camera.height);
  CHECK_EQ(frame.image.cols, frame.camera.width);
  CHECK(!mask_on() || !frame.mask.empty())
      << "mask term on a frame without a mask";
}

void RenderedFrameLoss::AttachDynamicChannel(const double* dynamic_logits,
                                             SplatView* view) {
  if (!mask_on()) return;
  const int n = view->count;
  probability_.resize(n);
  for (int i = 0; i < n; ++i) probability_[i] = Sigmoid(dynamic_logits[i]);
  view->num_extra = 1;
  view->extra = probability_.data();
}

double RenderedFrameLoss::Score(const RenderResult& render, const Frame& frame,
                                bool want_grad) {
  const size_t pixels =
      static_cast<size_t>(frame.camera.width) * frame.camera.height;
  double loss = 0;
  last_photometric_ = last_mask_ = 0;
  d_rgb_.clear();  // sized below, or by AddRgbGradient
  if (terms_.photometric_weight != 0) {
    d_rgb_.resize(3 * pixels);
    last_photometric_ = photometric_.Evaluate(
        render.rgb.data(), frame.image, terms_.photometric_weight,
        want_grad ? d_rgb_.data() : nullptr);
    loss += terms_.photometric_weight * last_photometric_;
  }
  if (mask_on()) {
    d_extra_.resize(pixels);
    last_mask_ =
        MaskBceLoss(render.extra.data(), frame.mask, terms_.mask_weight,
                    want_grad ? d_extra_.data() : nullptr);
    loss += terms_.mask_weight * last_mask_;
  }
  return loss;
}

void RenderedFrameLoss::AddRgbGradient(const double* extra, size_t size) {
  if (d_rgb_.empty()) d_rgb_.assign(size, 0.0);  // photometric term off
  CHECK_EQ(d_rgb_.size(), size);
  for (size_t i = 0; i < size; ++i) d_rgb_[i] += extra[i];
}

RenderGradients RenderedFrameLoss::ImageGradients() const {
  RenderGradients g;
  g.d_rgb = d_rgb_.empty() ? nullptr : d_rgb_.data();
  g.d_extra = mask_on() ? d_extra_.data() : nullptr;
  return g;
}

void RenderedFrameLoss::DynamicLogitGradient(const SplatGradients& grads,
                                             int count, double scale,
                                             double* out) const {
  if (!mask_on()) {
    std::fill(out, out + count, 0.0);
    return;
  }
  CHECK_EQ(static_cast<int>(probability_.size()), count);
  for (int i = 0; i < count; ++i) {
    const double p = probability_[i];
    out[i] = grads.extra[i] * p * (1 - p) * scale;
  }
}

}  // namespace es
