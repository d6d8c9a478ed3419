#include "costs/cuda/device_splat_render_cost.h"

#include <glog/logging.h>

#include "core/model/gaussians.h"
#include "costs/cuda/splat_cost_kernels.h"
#include "costs/scalar_loss.h"
#include "costs/splat_render_cost.h"

namespace es {
namespace cuda {

DeviceSplatRenderCost::DeviceSplatRenderCost(
    const ImageLossTerms& terms, const Eigen::Vector3d& background,
    DeviceRasterizer* rasterizer)
    : terms_(terms),
      background_(background),
      rasterizer_(rasterizer),
      photometric_(terms.ssim_weight) {
  CHECK(rasterizer_ != nullptr);
  set_num_residuals(1);
}

void DeviceSplatRenderCost::Reset(const Camera& camera, const float* image,
                                  const float* mask, int count,
                                  int sh_degree) {
  CHECK(image != nullptr || terms_.photometric_weight == 0)
      << "the photometric term needs the frame's image";
  CHECK(mask != nullptr || !mask_on())
      << "the mask term needs the frame's mask";
  camera_ = camera;
  image_ = image;
  mask_ = mask;
  count_ = count;
  sh_degree_ = sh_degree;
  *mutable_parameter_block_sizes() = SplatBlockSizes(count, sh_degree);
}

bool DeviceSplatRenderCost::Evaluate(double const* const* parameters,
                                     double* residuals,
                                     double** jacobians) const {
  DeviceSplatView view;
  ViewSplatBlocks(parameters, count_, sh_degree_, &view);
  if (mask_on()) {  // RenderedFrameLoss::AttachDynamicChannel
    probability_.Resize(count_);
    SigmoidArray(count_, parameters[kDynamicBlock], probability_.data());
    view.num_extra = 1;
    view.extra = probability_.data();
  }
  const DeviceImages& images =
      rasterizer_->ForwardDevice(camera_, view, background_);

  // RenderedFrameLoss::Score.
  const bool want_grad = jacobians != nullptr;
  const int w = camera_.width, h = camera_.height;
  const size_t pixels = static_cast<size_t>(w) * h;
  double loss = 0;
  last_photometric_ = last_mask_ = 0;
  DeviceImageGradients image_grads;
  if (terms_.photometric_weight != 0) {
    d_rgb_.Resize(3 * pixels);
    last_photometric_ = photometric_.Evaluate(
        images.rgb, image_, w, h, terms_.photometric_weight,
        want_grad ? d_rgb_.data() : nullptr);
    loss += terms_.photometric_weight * last_photometric_;
    image_grads.d_rgb = d_rgb_.data();
  }
  if (mask_on()) {
    d_extra_.Resize(pixels);
    last_mask_ = mask_loss_.Evaluate(images.extra, 1, 0, mask_, w, h,
                                     terms_.mask_weight,
                                     want_grad ? d_extra_.data() : nullptr);
    loss += terms_.mask_weight * last_mask_;
    image_grads.d_extra = d_extra_.data();
  }
  const double r = ScalarLossResidual(loss);
  residuals[0] = r;
  if (!want_grad) return true;

  // The backward writes every block; a constant block has no use here.
  for (int b = 0; b < kNumSplatBlocks; ++b)
    CHECK(jacobians[b] != nullptr)
        << "the device cost fills every Jacobian block";
  DeviceSplatGradients grads;
  PointAtSplatJacobians(jacobians, &grads);
  if (mask_on()) {
    d_probability_.Resize(count_);
    grads.extra = d_probability_.data();
  }
  rasterizer_->BackwardDevice(image_grads, grads);
  const double inv_r = 1.0 / r;
  for (int b = 0; b < kDynamicBlock; ++b)
    ScaleArray(parameter_block_sizes()[b], inv_r, jacobians[b]);
  double* dynamic = jacobians[kDynamicBlock];
  if (mask_on()) {
    DynamicLogitGradient(count_, d_probability_.data(), probability_.data(),
                         inv_r, dynamic);
  } else {
    DeviceZero(dynamic, sizeof(double) * count_);
  }
  return true;
}

double EvaluateDeviceScalarLossGradient(const ceres::CostFunction& cost,
                                        double const* const* parameters,
                                        double** gradients) {
  return EvaluateScalarLossGradientWith(cost, parameters, gradients,
                                        ScaleArray);
}

}  // namespace cuda
}  // namespace es
