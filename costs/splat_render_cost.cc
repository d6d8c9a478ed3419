#include "costs/splat_render_cost.h"

#include <glog/logging.h>

#include "costs/scalar_loss.h"

namespace es {

SplatRenderCost::SplatRenderCost(const Frame* frame, int count, int sh_degree,
                                 const ImageLossTerms& terms,
                                 const RenderOptions& options,
                                 Rasterizer* rasterizer)
    : options_(options),
      rasterizer_(rasterizer),
      loss_(terms, options) {
  if (!rasterizer_) {
    owned_rasterizer_ = std::make_unique<Rasterizer>();
    rasterizer_ = owned_rasterizer_.get();
  }
  set_num_residuals(1);
  Reset(frame, count, sh_degree);
}

void SplatRenderCost::Reset(const Frame* frame, int count, int sh_degree) {
  CHECK(frame != nullptr);
  loss_.CheckFrame(*frame);
  frame_ = frame;
  count_ = count;
  sh_degree_ = sh_degree;
  *mutable_parameter_block_sizes() = SplatBlockSizes(count, sh_degree);
}

std::vector<int32_t> SplatBlockSizes(int count, int sh_degree) {
  std::vector<int32_t> sizes;
  for (const GaussianArray& a : kGaussianArrays)
    sizes.push_back(a.Width(NumShCoeffs(sh_degree)) * count);
  return sizes;
}

std::vector<double*> SplatRenderCost::Blocks(GaussianSet* g) {
  std::vector<double*> blocks;
  for (const GaussianArray& a : kGaussianArrays)
    blocks.push_back((g->*a.values).data());
  return blocks;
}

bool SplatRenderCost::Evaluate(double const* const* parameters,
                               double* residuals, double** jacobians) const {
  SplatView view;
  ViewSplatBlocks(parameters, count_, sh_degree_, &view);
  loss_.AttachDynamicChannel(parameters[kDynamicBlock], &view);
  rasterizer_->Forward(frame_->camera, view, options_, &render_);

  const bool want_grad = jacobians != nullptr;
  const double r =
      ScalarLossResidual(loss_.Score(render_, *frame_, want_grad));
  residuals[0] = r;
  if (!want_grad) return true;

  rasterizer_->Backward(loss_.ImageGradients(), &grads_);
  const std::vector<double>* block_grads[] = {
      &grads_.means, &grads_.log_scales, &grads_.quats, &grads_.opacity_logits,
      &grads_.sh};
  for (int b = 0; b < kDynamicBlock; ++b) {
    if (jacobians[b] == nullptr) continue;
    ScalarLossJacobian(block_grads[b]->data(), parameter_block_sizes()[b], r,
                       jacobians[b]);
  }
  if (double* jac = jacobians[kDynamicBlock])
    loss_.DynamicLogitGradient(grads_, count_, 1.0 / r, jac);
  return true;
}

ceres::CostFunction* CreatePhotometricCost(const Frame* frame, int count,
                                           int sh_degree, double ssim_weight,
                                           const RenderOptions& options) {
  return new SplatRenderCost(frame, count, sh_degree,
                             PhotometricOnlyTerms(ssim_weight), options);
}

ceres::CostFunction* CreateMaskBceCost(const Frame* frame, int count,
                                       int sh_degree,
                                       const RenderOptions& options) {
  return new SplatRenderCost(frame, count, sh_degree, MaskOnlyTerms(),
                             options);
}

}  // namespace es
