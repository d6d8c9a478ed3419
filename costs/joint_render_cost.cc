#include "costs/joint_render_cost.h"

#include <algorithm>

#include <glog/logging.h>

#include "costs/mask_bce_loss.h"
#include "costs/photometric_loss.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"

namespace es {

LoopStructure LoopStructure::Of(const LoopModel& model) {
  LoopStructure s;
  s.count = model.gaussians.size();
  s.sh_degree = model.gaussians.sh_degree;
  s.dynamic_index = &model.dynamic_index;
  s.start_times = &model.start_times;
  s.cycle_length = model.cycle_length;
  s.motion = model.motion ? &*model.motion : nullptr;
  s.residual = model.residual ? &*model.residual : nullptr;
  return s;
}

JointBlockLayout::JointBlockLayout(const LoopStructure& s) {
  const int n = s.count;
  sizes_ = {3 * n, 3 * n, 4 * n, n, 3 * NumShCoeffs(s.sh_degree) * n, n};
  if (s.motion != nullptr) {
    motion_ = num_blocks();
    sizes_.push_back(s.motion->triplane().num_params());
    sizes_.push_back(s.motion->mlp().num_params());
  }
  if (s.residual != nullptr) {
    residual_ = num_blocks();
    sizes_.push_back(s.residual->triplane().num_params());
    sizes_.push_back(s.residual->mlp().num_params());
  }
}

std::vector<double*> JointBlocks(LoopModel* model) {
  std::vector<double*> blocks = SplatRenderCost::Blocks(&model->gaussians);
  if (model->motion) {
    blocks.push_back(model->motion->triplane_params().data());
    blocks.push_back(model->motion->mlp_params().data());
  }
  if (model->residual) {
    blocks.push_back(model->residual->triplane_params().data());
    blocks.push_back(model->residual->mlp_params().data());
  }
  return blocks;
}

JointRenderCost::JointRenderCost(const Frame* frame, int frame_index,
                                 const LoopStructure& structure,
                                 const JointRenderTerms& terms,
                                 const RenderOptions& options,
                                 Rasterizer* rasterizer)
    : layout_(structure),
      terms_(terms),
      options_(options),
      rasterizer_(rasterizer) {
  if (!rasterizer_) {
    owned_rasterizer_ = std::make_unique<Rasterizer>();
    rasterizer_ = owned_rasterizer_.get();
  }
  set_num_residuals(1);
  Reset(frame, frame_index, structure);
}

void JointRenderCost::Reset(const Frame* frame, int frame_index,
                            const LoopStructure& structure) {
  CHECK(frame != nullptr);
  CHECK_EQ(frame->image.rows, frame->camera.height);
  CHECK_EQ(frame->image.cols, frame->camera.width);
  CHECK(terms_.mask_weight == 0 || !frame->mask.empty())
      << "mask term on a frame without a mask";
  CHECK(structure.dynamic_index != nullptr &&
        structure.start_times != nullptr);
  CHECK_EQ(structure.dynamic_index->size(), structure.start_times->size());
  frame_ = frame;
  frame_index_ = frame_index;
  structure_ = structure;
  layout_ = JointBlockLayout(structure);
  *mutable_parameter_block_sizes() = layout_.sizes();
}

LoopSplatView JointRenderCost::View(double const* const* parameters) const {
  LoopSplatView v;
  SplatView& c = v.canonical;
  c.count = structure_.count;
  c.sh_degree = structure_.sh_degree;
  c.means = parameters[kMeansBlock];
  c.log_scales = parameters[kLogScalesBlock];
  c.quats = parameters[kQuatsBlock];
  c.opacity_logits = parameters[kOpacityBlock];
  c.sh = parameters[kShBlock];
  v.num_dynamic = static_cast<int>(structure_.dynamic_index->size());
  v.dynamic_index = structure_.dynamic_index->data();
  v.start_times = structure_.start_times->data();
  v.cycle_length = structure_.cycle_length;
  v.motion = structure_.motion;
  v.residual = structure_.residual;
  if (v.motion != nullptr) {
    v.motion_params = {parameters[layout_.motion_triplane()],
                       parameters[layout_.motion_mlp()]};
  }
  if (v.residual != nullptr) {
    v.residual_params = {parameters[layout_.residual_triplane()],
                         parameters[layout_.residual_mlp()]};
  }
  return v;
}

bool JointRenderCost::Evaluate(double const* const* parameters,
                               double* residuals, double** jacobians) const {
  const int n = structure_.count;
  const bool photometric_on = terms_.photometric_weight != 0;
  const bool mask_on = terms_.mask_weight != 0;
  const bool residual_on =
      terms_.residual_weight != 0 && structure_.residual != nullptr;
  LoopSplatView model = View(parameters);
  if (mask_on) {
    probability_.resize(n);
    const double* logits = parameters[kDynamicBlock];
    for (int i = 0; i < n; ++i) probability_[i] = Sigmoid(logits[i]);
    model.canonical.num_extra = 1;
    model.canonical.extra = probability_.data();
  }
  const SplatView& view = composer_.Compose(model, frame_index_);
  rasterizer_->Forward(frame_->camera, view, options_, &render_);

  const bool want_grad = jacobians != nullptr;
  const size_t pixels =
      static_cast<size_t>(frame_->camera.width) * frame_->camera.height;
  double loss = 0;
  last_photometric_ = last_mask_ = last_residual_ = 0;
  if (photometric_on) {
    d_rgb_.resize(3 * pixels);
    last_photometric_ = PhotometricLoss(
        render_.rgb.data(), frame_->image, terms_.ssim_weight,
        terms_.photometric_weight, want_grad ? d_rgb_.data() : nullptr);
    loss += terms_.photometric_weight * last_photometric_;
  }
  if (mask_on) {
    d_extra_.resize(pixels);
    last_mask_ = MaskBceLoss(render_.extra.data(), frame_->mask,
                             terms_.mask_weight,
                             want_grad ? d_extra_.data() : nullptr);
    loss += terms_.mask_weight * last_mask_;
  }
  if (residual_on) {
    d_residuals_.resize(composer_.residuals().size());
    last_residual_ =
        ResidualL2Loss(composer_.residuals(), terms_.residual_weight,
                       want_grad ? d_residuals_.data() : nullptr);
    loss += terms_.residual_weight * last_residual_;
  }
  const double r = ScalarLossResidual(loss);
  residuals[0] = r;
  if (!want_grad) return true;

  // Gradients accumulate into the Jacobian rows, then are divided by r.
  const std::vector<int32_t>& sizes = layout_.sizes();
  for (int b = 0; b < layout_.num_blocks(); ++b)
    if (jacobians[b]) std::fill(jacobians[b], jacobians[b] + sizes[b], 0.0);

  RenderGradients image_grads;
  image_grads.d_rgb = photometric_on ? d_rgb_.data() : nullptr;
  image_grads.d_extra = mask_on ? d_extra_.data() : nullptr;
  rasterizer_->Backward(image_grads, &grads_);

  LoopSplatGradients out;
  out.means = jacobians[kMeansBlock];
  out.log_scales = jacobians[kLogScalesBlock];
  out.quats = jacobians[kQuatsBlock];
  out.opacity_logits = jacobians[kOpacityBlock];
  out.sh = jacobians[kShBlock];
  if (layout_.motion_triplane() >= 0) {
    out.motion = {jacobians[layout_.motion_triplane()],
                  jacobians[layout_.motion_mlp()]};
  }
  if (layout_.residual_triplane() >= 0) {
    out.residual = {jacobians[layout_.residual_triplane()],
                    jacobians[layout_.residual_mlp()]};
  }
  composer_.Backward(model, grads_,
                     residual_on ? d_residuals_.data() : nullptr, out);
  if (double* jac = jacobians[kDynamicBlock]; jac && mask_on) {
    // The extra channel is the canonical probability (D does not touch it).
    for (int i = 0; i < n; ++i) {
      const double p = probability_[i];
      jac[i] = grads_.extra[i] * p * (1 - p);
    }
  }
  const double inv_r = 1.0 / r;
  for (int b = 0; b < layout_.num_blocks(); ++b) {
    if (!jacobians[b]) continue;
    double* jac = jacobians[b];
    const int size = sizes[b];
#pragma omp parallel for if (size > 65536) schedule(static)
    for (int i = 0; i < size; ++i) jac[i] *= inv_r;
  }
  return true;
}

ceres::CostFunction* CreateJointPhotometricCost(
    const Frame* frame, int frame_index, const LoopStructure& structure,
    double ssim_weight, const RenderOptions& options) {
  JointRenderTerms terms;
  terms.photometric_weight = 1.0;
  terms.ssim_weight = ssim_weight;
  return new JointRenderCost(frame, frame_index, structure, terms, options);
}

ceres::CostFunction* CreateJointMaskBceCost(const Frame* frame,
                                            int frame_index,
                                            const LoopStructure& structure,
                                            const RenderOptions& options) {
  JointRenderTerms terms;
  terms.photometric_weight = 0.0;
  terms.mask_weight = 1.0;
  return new JointRenderCost(frame, frame_index, structure, terms, options);
}

}  // namespace es
