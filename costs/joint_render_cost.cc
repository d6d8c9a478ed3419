#include "costs/joint_render_cost.h"

#include <algorithm>

#include <glog/logging.h>

#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"

namespace es {

JointBlockLayout::JointBlockLayout(const LoopStructure& s) {
  sizes_ = SplatBlockSizes(s.count, s.sh_degree);
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

namespace {

FieldParams FieldBlocks(double const* const* parameters, int triplane) {
  if (triplane < 0) return {};
  return {parameters[triplane], parameters[triplane + 1]};
}

FieldGradients FieldGradientBlocks(double* const* gradients,
                                   char* const* triplane_chunks,
                                   int triplane) {
  if (triplane < 0) return {};
  return {gradients[triplane], gradients[triplane + 1],
          triplane_chunks != nullptr ? triplane_chunks[triplane] : nullptr};
}

}  // namespace

FieldParams JointBlockLayout::MotionParams(
    double const* const* parameters) const {
  return FieldBlocks(parameters, motion_);
}

FieldParams JointBlockLayout::ResidualParams(
    double const* const* parameters) const {
  return FieldBlocks(parameters, residual_);
}

FieldGradients JointBlockLayout::MotionGradients(
    double* const* gradients, char* const* triplane_chunks) const {
  return FieldGradientBlocks(gradients, triplane_chunks, motion_);
}

FieldGradients JointBlockLayout::ResidualGradients(
    double* const* gradients, char* const* triplane_chunks) const {
  return FieldGradientBlocks(gradients, triplane_chunks, residual_);
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
                                 Rasterizer* rasterizer,
                                 const EulerOptions& euler)
    : layout_(structure),
      residual_weight_(terms.residual_weight),
      options_(options),
      rasterizer_(rasterizer),
      image_loss_(terms, options),
      composer_(euler) {
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
  image_loss_.CheckFrame(*frame);
  CHECK(structure.dynamic_index != nullptr &&
        structure.start_times != nullptr);
  CHECK_EQ(structure.dynamic_index->size(), structure.start_times->size());
  frame_ = frame;
  frame_index_ = frame_index;
  structure_ = structure;
  layout_ = JointBlockLayout(structure);
  *mutable_parameter_block_sizes() = layout_.sizes();
}

void JointRenderCost::RecomposeFrom(const JointRenderCost* source) {
  CHECK(source != nullptr && source != this && cycle_number_);
  source_ = source;
}

LoopModelView JointRenderCost::View(double const* const* parameters) const {
  LoopModelView v;
  v.structure = structure_;
  ViewSplatBlocks(parameters, structure_.count, structure_.sh_degree,
                  &v.canonical);
  v.motion_params = layout_.MotionParams(parameters);
  v.residual_params = layout_.ResidualParams(parameters);
  return v;
}

LoopModelView JointRenderCost::AttachedView(
    double const* const* parameters) const {
  LoopModelView model = View(parameters);
  image_loss_.AttachDynamicChannel(parameters[kDynamicBlock],
                                   &model.canonical);
  return model;
}

double JointRenderCost::HalfSquaredLoss(const LoopModelView& model) const {
  const double r = ScalarLossResidual(Forward(model, true));
  return 0.5 * r * r;
}

bool JointRenderCost::Evaluate(double const* const* parameters,
                               double* residuals, double** jacobians) const {
  const LoopModelView model = AttachedView(parameters);
  const double r = ScalarLossResidual(Forward(model, jacobians != nullptr));
  residuals[0] = r;
  if (jacobians == nullptr) return true;
  Backward(model, jacobians);
  const std::vector<int32_t>& sizes = layout_.sizes();
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

double JointRenderCost::LossGradient(double const* const* parameters,
                                     double** gradients) const {
  const LoopModelView model = AttachedView(parameters);
  const double loss = HalfSquaredLoss(model);
  Backward(model, gradients);
  return loss;
}

double JointRenderCost::AddLossGradient(double const* const* parameters,
                                        double** gradients,
                                        char* const* triplane_chunks) const {
  const LoopModelView model = AttachedView(parameters);
  const double loss = HalfSquaredLoss(model);
  Backward(model, gradients, /*accumulate=*/true, triplane_chunks);
  return loss;
}

double JointRenderCost::RenderForGradient(
    double const* const* parameters) const {
  return HalfSquaredLoss(AttachedView(parameters));
}

void JointRenderCost::BackwardWithImageGradient(
    double const* const* parameters, const double* extra_d_rgb,
    double** gradients, bool accumulate,
    char* const* triplane_chunks) const {
  const LoopModelView model = AttachedView(parameters);
  if (extra_d_rgb) image_loss_.AddRgbGradient(extra_d_rgb, render_.rgb.size());
  Backward(model, gradients, accumulate, triplane_chunks);
}

double JointRenderCost::Forward(const LoopModelView& model,
                                bool want_grad) const {
  const SplatView* view;
  if (source_ != nullptr) {
    CHECK_EQ(source_->frame_index_, frame_index_)
        << "recomposing another frame than the source's";
    view = &composer().Recompose(model, *cycle_number_);
  } else {
    view = &composer_.Compose(model, frame_index_, cycle_number_);
  }
  rasterizer_->Forward(frame_->camera, *view, options_, &render_);
  double loss = image_loss_.Score(render_, *frame_, want_grad);
  last_residual_ = 0;
  if (residual_on()) {
    d_residuals_.resize(composer().residuals().size());
    last_residual_ =
        ResidualL2Loss(composer().residuals(), residual_weight_,
                       want_grad ? d_residuals_.data() : nullptr);
    loss += residual_weight_ * last_residual_;
  }
  return loss;
}

void JointRenderCost::Backward(const LoopModelView& model,
                               double** jacobians, bool accumulate,
                               char* const* triplane_chunks) const {
  // Gradients accumulate into the rows.
  const std::vector<int32_t>& sizes = layout_.sizes();
  for (int b = 0; !accumulate && b < layout_.num_blocks(); ++b)
    if (jacobians[b]) std::fill(jacobians[b], jacobians[b] + sizes[b], 0.0);

  rasterizer_->Backward(image_loss_.ImageGradients(), &grads_);

  LoopModelGradients out;
  PointAtSplatJacobians(jacobians, &out);
  out.motion = layout_.MotionGradients(jacobians, triplane_chunks);
  out.residual = layout_.ResidualGradients(jacobians, triplane_chunks);
  composer().Backward(model, grads_,
                     residual_on() ? d_residuals_.data() : nullptr, out);
  // The extra channel is the canonical probability (D does not touch it).
  double* jac = jacobians[kDynamicBlock];
  if (jac == nullptr) return;
  if (!accumulate) {
    image_loss_.DynamicLogitGradient(grads_, structure_.count, 1.0, jac);
    return;
  }
  dynamic_logit_grad_.resize(structure_.count);
  image_loss_.DynamicLogitGradient(grads_, structure_.count, 1.0,
                                   dynamic_logit_grad_.data());
  for (int i = 0; i < structure_.count; ++i) jac[i] += dynamic_logit_grad_[i];
}

ceres::CostFunction* CreateJointPhotometricCost(
    const Frame* frame, int frame_index, const LoopStructure& structure,
    double ssim_weight, const RenderOptions& options) {
  return new JointRenderCost(frame, frame_index, structure,
                             {PhotometricOnlyTerms(ssim_weight)}, options);
}

ceres::CostFunction* CreateJointMaskBceCost(const Frame* frame,
                                            int frame_index,
                                            const LoopStructure& structure,
                                            const RenderOptions& options) {
  return new JointRenderCost(frame, frame_index, structure, {MaskOnlyTerms()},
                             options);
}

}  // namespace es
