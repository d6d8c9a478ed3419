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
    : background_(background), rasterizer_(rasterizer), loss_(terms) {
  CHECK(rasterizer_ != nullptr);
  set_num_residuals(1);
}

void DeviceSplatRenderCost::Reset(const Camera& camera, const float* image,
                                  const float* mask, int count,
                                  int sh_degree) {
  loss_.SetFrame(camera, image, mask);
  count_ = count;
  sh_degree_ = sh_degree;
  *mutable_parameter_block_sizes() = SplatBlockSizes(count, sh_degree);
}

bool DeviceSplatRenderCost::Evaluate(double const* const* parameters,
                                     double* residuals,
                                     double** jacobians) const {
  DeviceSplatView view;
  ViewSplatBlocks(parameters, count_, sh_degree_, &view);
  loss_.AttachDynamicChannel(parameters[kDynamicBlock], &view);
  const DeviceImages& images =
      rasterizer_->ForwardDevice(loss_.camera(), view, background_);
  const bool want_grad = jacobians != nullptr;
  const double loss = loss_.Score(images, want_grad);
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
  rasterizer_->BackwardDevice(loss_.ImageGradients(), grads);
  const double inv_r = 1.0 / r;
  for (int b = 0; b < kDynamicBlock; ++b)
    ScaleArray(parameter_block_sizes()[b], inv_r, jacobians[b]);
  double* dynamic = jacobians[kDynamicBlock];
  if (mask_on()) {
    DynamicLogitGradient(count_, d_probability_.data(), loss_.probability(),
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
