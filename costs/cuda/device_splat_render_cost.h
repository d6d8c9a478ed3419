#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_SPLAT_RENDER_COST_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_SPLAT_RENDER_COST_H_

// SplatRenderCost (costs/splat_render_cost.h) on a CUDA device: the same
// ceres::CostFunction, one residual r = sqrt(2 l + eps) of
//   l = w_p * photometric(rgb, image) + w_m * BCE(dynamic channel, mask)
// over the six SplatBlock parameter blocks, whose Evaluate receives device
// parameter blocks and fills device Jacobian blocks (dl/dtheta / r); only
// the residual and the terms' sums cross to the host. It renders with
// DeviceRasterizer (float, as the CPU's default float path) and scores
// with DevicePhotometricLoss and DeviceMaskBceLoss. No CUDA types.
//
// A ceres::Problem would read the blocks as host memory, so the cost is
// for callers that evaluate it directly (EvaluateDeviceScalarLossGradient).

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "costs/cuda/device_rendered_frame_loss.h"
#include "costs/rendered_frame_loss.h"

namespace es {
namespace cuda {

// Evaluate reuses internal buffers: not thread-safe.
class DeviceSplatRenderCost : public ceres::CostFunction {
 public:
  // `rasterizer` must outlive the cost; densification reads its last
  // render's statistics.
  DeviceSplatRenderCost(const ImageLossTerms& terms,
                        const Eigen::Vector3d& background,
                        DeviceRasterizer* rasterizer);

  // Points the cost at a frame: its camera, its image (device, H W 3
  // floats, RGB in [0, 1]) and, with the mask term on, its mask (device,
  // H W floats in [0, 1]), and at a model size. The arrays must stay alive
  // and unchanged while the cost uses them.
  void Reset(const Camera& camera, const float* image, const float* mask,
             int count, int sh_degree);

  // parameters: the six device blocks (SplatBlock order); jacobians:
  // nullptr, or six device blocks of the same sizes, every value written
  // (the dynamic block's zeros with the mask term off).
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  bool mask_on() const { return loss_.mask_on(); }
  // The unweighted terms of the last Evaluate (0 for a disabled term).
  double last_photometric() const { return loss_.last_photometric(); }
  double last_mask() const { return loss_.last_mask(); }

 private:
  Eigen::Vector3d background_;
  DeviceRasterizer* rasterizer_;
  int count_ = 0;
  int sh_degree_ = 0;
  // Reused between evaluations.
  mutable DeviceRenderedFrameLoss loss_;
  mutable DeviceBuffer<double> d_probability_;
};

// EvaluateScalarLossGradient (costs/scalar_loss.h) for a cost with device
// blocks: evaluates into the device gradient blocks and multiplies each
// Jacobian row back by r, leaving dl/dtheta there. Returns 0.5 r^2 =
// l + eps / 2.
double EvaluateDeviceScalarLossGradient(const ceres::CostFunction& cost,
                                        double const* const* parameters,
                                        double** gradients);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_SPLAT_RENDER_COST_H_
