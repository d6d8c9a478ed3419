#ifndef EULERSPLAT_COSTS_RENDERED_FRAME_LOSS_H_
#define EULERSPLAT_COSTS_RENDERED_FRAME_LOSS_H_

#include <cstddef>
#include <vector>

#include "core/io/scene.h"
#include "core/render/rasterizer.h"
#include "costs/photometric_loss.h"

namespace es {

// Which image-space terms a render cost sums, and their weights. A zero
// weight turns a term off (it is then neither computed nor differentiated).
struct ImageLossTerms {
  double photometric_weight = 1.0;  // (1 - s) L1 + s (1 - SSIM)
  double ssim_weight = 0.2;         // s above
  double mask_weight = 0.0;         // BCE of the dynamic channel vs the mask
  // Memory the targets' SSIM statistics may keep between evaluations.
  size_t ssim_cache_bytes = kDefaultSsimCacheBytes;
};

// The single-term recipes (the Create*Cost factories'): one term at
// weight 1, the other off.
ImageLossTerms PhotometricOnlyTerms(double ssim_weight);
ImageLossTerms MaskOnlyTerms();

// The image-space half that SplatRenderCost and JointRenderCost share:
//   l = w_p * photometric(rgb, image) + w_m * BCE(dynamic channel, mask).
// The dynamic channel renders sigmoid(dynamic_logit) composited like a
// colour, as the paper does, so the mask gradient also reaches the
// geometry (detaching it would cost a second Backward). Reuses its
// buffers between frames: not thread-safe.
class RenderedFrameLoss {
 public:
  // The losses run in the renders' precision and instruction set
  // (options.use_double, options.simd).
  RenderedFrameLoss(const ImageLossTerms& terms, const RenderOptions& options);

  const ImageLossTerms& terms() const { return terms_; }
  bool mask_on() const { return terms_.mask_weight != 0; }

  // CHECKs that `frame` can be scored: image of the camera's size, and a
  // mask when the mask term is on.
  void CheckFrame(const Frame& frame) const;

  // With the mask term on, makes sigmoid(dynamic_logits) (view->count of
  // them) the view's one extra channel; otherwise leaves the view alone.
  void AttachDynamicChannel(const double* dynamic_logits, SplatView* view);

  // The weighted loss of `render` against `frame`. With want_grad it keeps
  // d loss / d image for ImageGradients.
  double Score(const RenderResult& render, const Frame& frame,
               bool want_grad);

  // Adds `extra` (H x W x 3, the last Score's frame size) to the kept
  // d loss / d image: a loss on the render that this class does not know
  // (e.g. one across frames), `size` = H x W x 3 of the last Score.
  void AddRgbGradient(const double* extra, size_t size);

  // Rasterizer::Backward's input for the last Score(want_grad = true).
  RenderGradients ImageGradients() const;

  // scale * d loss / d dynamic_logit for the `count` logits of the last
  // AttachDynamicChannel, from the Backward's extra-channel gradient (zero
  // with the mask term off).
  void DynamicLogitGradient(const SplatGradients& grads, int count,
                            double scale, double* out) const;

  // The unweighted terms of the last Score (0 for a disabled term).
  double last_photometric() const { return last_photometric_; }
  double last_mask() const { return last_mask_; }

 private:
  ImageLossTerms terms_;
  PhotometricLoss photometric_;
  std::vector<double> probability_, d_rgb_, d_extra_;
  double last_photometric_ = 0, last_mask_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_RENDERED_FRAME_LOSS_H_
