#include "costs/splat_render_cost.h"

#include <glog/logging.h>

#include <algorithm>

#include "costs/mask_bce_loss.h"
#include "costs/photometric_loss.h"
#include "costs/scalar_loss.h"

namespace es {

SplatRenderCost::SplatRenderCost(const Frame* frame, int count, int sh_degree,
                                 const SplatRenderTerms& terms,
                                 const RenderOptions& options,
                                 Rasterizer* rasterizer)
    : terms_(terms), options_(options), rasterizer_(rasterizer) {
  if (!rasterizer_) {
    owned_rasterizer_ = std::make_unique<Rasterizer>();
    rasterizer_ = owned_rasterizer_.get();
  }
  set_num_residuals(1);
  Reset(frame, count, sh_degree);
}

void SplatRenderCost::Reset(const Frame* frame, int count, int sh_degree) {
  CHECK(frame != nullptr);
  CHECK_EQ(frame->image.rows, frame->camera.height);
  CHECK_EQ(frame->image.cols, frame->camera.width);
  CHECK(terms_.mask_weight == 0 || !frame->mask.empty())
      << "mask term on a frame without a mask";
  frame_ = frame;
  count_ = count;
  sh_degree_ = sh_degree;
  const int k = NumShCoeffs(sh_degree);
  *mutable_parameter_block_sizes() = {3 * count, 3 * count,     4 * count,
                                      count,     3 * k * count, count};
}

std::vector<double*> SplatRenderCost::Blocks(GaussianSet* g) {
  return {g->means.data(), g->log_scales.data(),
          g->quats.data(), g->opacity_logits.data(),
          g->sh.data(),    g->dynamic_logits.data()};
}

bool SplatRenderCost::Evaluate(double const* const* parameters,
                               double* residuals, double** jacobians) const {
  const int n = count_;
  const bool photometric_on = terms_.photometric_weight != 0;
  const bool mask_on = terms_.mask_weight != 0;
  SplatView view;
  view.count = n;
  view.sh_degree = sh_degree_;
  view.means = parameters[kMeansBlock];
  view.log_scales = parameters[kLogScalesBlock];
  view.quats = parameters[kQuatsBlock];
  view.opacity_logits = parameters[kOpacityBlock];
  view.sh = parameters[kShBlock];
  if (mask_on) {
    probability_.resize(n);
    const double* logits = parameters[kDynamicBlock];
    for (int i = 0; i < n; ++i) probability_[i] = Sigmoid(logits[i]);
    view.num_extra = 1;
    view.extra = probability_.data();
  }
  rasterizer_->Forward(frame_->camera, view, options_, &render_);

  const bool want_grad = jacobians != nullptr;
  const size_t pixels =
      static_cast<size_t>(frame_->camera.width) * frame_->camera.height;
  double loss = 0;
  last_photometric_ = last_mask_ = 0;
  if (photometric_on) {
    d_rgb_.resize(3 * pixels);
    last_photometric_ = PhotometricLoss(
        render_.rgb.data(), frame_->image, terms_.ssim_weight,
        terms_.photometric_weight, want_grad ? d_rgb_.data() : nullptr);
    loss += terms_.photometric_weight * last_photometric_;
  }
  if (mask_on) {
    d_extra_.resize(pixels);
    last_mask_ =
        MaskBceLoss(render_.extra.data(), frame_->mask, terms_.mask_weight,
                    want_grad ? d_extra_.data() : nullptr);
    loss += terms_.mask_weight * last_mask_;
  }
  const double r = ScalarLossResidual(loss);
  residuals[0] = r;
  if (!want_grad) return true;

  RenderGradients image_grads;
  image_grads.d_rgb = photometric_on ? d_rgb_.data() : nullptr;
  image_grads.d_extra = mask_on ? d_extra_.data() : nullptr;
  rasterizer_->Backward(image_grads, &grads_);
  const std::vector<double>* block_grads[] = {
      &grads_.means, &grads_.log_scales, &grads_.quats, &grads_.opacity_logits,
      &grads_.sh};
  for (int b = 0; b < kDynamicBlock; ++b) {
    if (jacobians[b] == nullptr) continue;
    ScalarLossJacobian(block_grads[b]->data(), parameter_block_sizes()[b], r,
                       jacobians[b]);
  }
  if (double* jac = jacobians[kDynamicBlock]) {
    if (!mask_on) {
      std::fill(jac, jac + n, 0.0);
    } else {
      const double inv_r = 1.0 / r;
      for (int i = 0; i < n; ++i) {
        const double p = probability_[i];
        jac[i] = grads_.extra[i] * p * (1 - p) * inv_r;
      }
    }
  }
  return true;
}

ceres::CostFunction* CreatePhotometricCost(const Frame* frame, int count,
                                           int sh_degree, double ssim_weight,
                                           const RenderOptions& options) {
  SplatRenderTerms terms;
  terms.photometric_weight = 1.0;
  terms.ssim_weight = ssim_weight;
  terms.mask_weight = 0.0;
  return new SplatRenderCost(frame, count, sh_degree, terms, options);
}

ceres::CostFunction* CreateMaskBceCost(const Frame* frame, int count,
                                       int sh_degree,
                                       const RenderOptions& options) {
  SplatRenderTerms terms;
  terms.photometric_weight = 0.0;
  terms.mask_weight = 1.0;
  return new SplatRenderCost(frame, count, sh_degree, terms, options);
}

}  // namespace es
