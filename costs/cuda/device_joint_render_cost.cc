#include "costs/cuda/device_joint_render_cost.h"

#include <glog/logging.h>

#include "core/fields/residual_field.h"
#include "core/model/gaussians.h"
#include "costs/cuda/splat_cost_kernels.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"

namespace es {
namespace cuda {

DeviceJointRenderCost::DeviceJointRenderCost(const JointRenderTerms& terms,
                                             const Eigen::Vector3d& background,
                                             DeviceRasterizer* rasterizer,
                                             const EulerOptions& euler)
    : residual_weight_(terms.residual_weight),
      background_(background),
      rasterizer_(rasterizer),
      layout_(LoopStructure()),
      composer_(euler),
      image_loss_(terms) {
  CHECK(rasterizer_ != nullptr);
  set_num_residuals(1);
}

void DeviceJointRenderCost::Reset(const Camera& camera, const float* image,
                                  const float* mask, int frame_index,
                                  const LoopStructure& structure) {
  image_loss_.SetFrame(camera, image, mask);
  composer_.SetStructure(structure);
  frame_index_ = frame_index;
  structure_ = structure;
  layout_ = JointBlockLayout(structure);
  *mutable_parameter_block_sizes() = layout_.sizes();
}

DeviceLoopModelView DeviceJointRenderCost::View(
    double const* const* parameters, bool attach) const {
  DeviceLoopModelView v;
  DeviceSplatView& c = v.canonical;
  ViewSplatBlocks(parameters, structure_.count, structure_.sh_degree, &c);
  if (attach) image_loss_.AttachDynamicChannel(parameters[kDynamicBlock], &c);
  v.motion_params = layout_.MotionParams(parameters);
  v.residual_params = layout_.ResidualParams(parameters);
  return v;
}

double DeviceJointRenderCost::Forward(double const* const* parameters,
                                      bool want_grad) const {
  const DeviceSplatView& view =
      composer_.Compose(View(parameters, /*attach=*/true), frame_index_,
                        cycle_number_);
  render_ = rasterizer_->ForwardDevice(image_loss_.camera(), view,
                                      background_);

  // RenderedFrameLoss::Score, then D's L2.
  double loss = image_loss_.Score(render_, want_grad);
  last_residual_ = 0;
  if (residual_on()) {
    const long long outputs =
        static_cast<long long>(composer_.num_dynamic()) * kResidualDim;
    d_residuals_.Resize(outputs);
    last_residual_ = residual_loss_.Evaluate(
        composer_.residuals(), outputs, residual_weight_,
        want_grad ? d_residuals_.data() : nullptr);
    loss += residual_weight_ * last_residual_;
  }
  gradients_ready_ = want_grad;
  return loss;
}

void DeviceJointRenderCost::Backward(double const* const* parameters,
                                     double** gradients) const {
  CHECK(gradients_ready_)
      << "DeviceJointRenderCost: a backward without a forward for it";
  const int count = structure_.count;
  splat_grads_.Resize(count, structure_.sh_degree, mask_on() ? 1 : 0);
  const DeviceSplatGradients grads = splat_grads_.View();
  rasterizer_->BackwardDevice(image_loss_.ImageGradients(), grads);

  LoopModelGradients out;
  PointAtSplatJacobians(gradients, &out);
  // The device triplane gradient is dense: no chunk flags.
  out.motion = layout_.MotionGradients(gradients, nullptr);
  out.residual = layout_.ResidualGradients(gradients, nullptr);
  composer_.Backward(View(parameters, /*attach=*/false), grads,
                     residual_on() ? d_residuals_.data() : nullptr, out);
  // The extra channel is the canonical probability (D does not touch it).
  double* dynamic = gradients[kDynamicBlock];
  if (dynamic != nullptr && mask_on()) {
    AddDynamicLogitGradient(count, grads.extra, image_loss_.probability(),
                            1.0, dynamic);
  }
}

bool DeviceJointRenderCost::Evaluate(double const* const* parameters,
                                     double* residuals,
                                     double** jacobians) const {
  const double r =
      ScalarLossResidual(Forward(parameters, jacobians != nullptr));
  residuals[0] = r;
  if (jacobians == nullptr) return true;
  const std::vector<int32_t>& sizes = layout_.sizes();
  for (int b = 0; b < layout_.num_blocks(); ++b) {
    if (jacobians[b] != nullptr)
      DeviceZero(jacobians[b], sizeof(double) * sizes[b]);
  }
  Backward(parameters, jacobians);
  const double inv_r = 1.0 / r;
  for (int b = 0; b < layout_.num_blocks(); ++b) {
    if (jacobians[b] != nullptr) ScaleArray(sizes[b], inv_r, jacobians[b]);
  }
  return true;
}

double DeviceJointRenderCost::AddLossGradient(double const* const* parameters,
                                              double** gradients) const {
  const double loss = RenderForGradient(parameters);
  Backward(parameters, gradients);
  return loss;
}

double DeviceJointRenderCost::RenderForGradient(
    double const* const* parameters) const {
  const double r = ScalarLossResidual(Forward(parameters, true));
  return 0.5 * r * r;
}

void DeviceJointRenderCost::BackwardWithImageGradient(
    double const* const* parameters, const float* extra_d_rgb,
    double** gradients, bool accumulate) const {
  if (extra_d_rgb != nullptr) {
    CHECK(gradients_ready_) << "BackwardWithImageGradient before "
                               "RenderForGradient";
    image_loss_.AddRgbGradient(extra_d_rgb);
  }
  if (!accumulate) {
    const std::vector<int32_t>& sizes = layout_.sizes();
    for (int b = 0; b < layout_.num_blocks(); ++b) {
      if (gradients[b] != nullptr)
        DeviceZero(gradients[b], sizeof(double) * sizes[b]);
    }
  }
  Backward(parameters, gradients);
}

}  // namespace cuda
}  // namespace es
