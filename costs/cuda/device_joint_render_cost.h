#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_RENDER_COST_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_RENDER_COST_H_

// JointRenderCost (costs/joint_render_cost.h) on a CUDA device: the
// joint-training loss of one frame i,
//   l = w_p photometric + w_m BCE(dynamic channel, mask) + w_r D L2,
// as one residual r = sqrt(2 l + eps) over the JointBlockLayout blocks,
// which are device arrays here, as are the Jacobian and gradient blocks.
// The frame is composed by DeviceFrameComposer (Alg. 1 with V, D at
// (x0, t, p)), rendered by DeviceRasterizer (float, as the CPU's default
// float path), scored by DevicePhotometricLoss, DeviceMaskBceLoss and
// DeviceResidualL2Loss, and differentiated back through the rasterizer, D
// and the Euler chain; only the terms' sums and the chain's counts cross
// to the host. No CUDA types.
//
// A ceres::Problem would read the blocks as host memory, so the cost is
// for callers that evaluate it directly (EvaluateDeviceScalarLossGradient,
// AddLossGradient).

#include <optional>

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include "core/loop/cuda/device_frame_composer.h"
#include "core/loop/euler_chain.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "core/render/cuda/device_splats.h"
#include "costs/cuda/device_rendered_frame_loss.h"
#include "costs/cuda/device_residual_l2_loss.h"
#include "costs/joint_render_cost.h"

namespace es {
namespace cuda {

// Evaluate reuses internal buffers: not thread-safe.
class DeviceJointRenderCost : public ceres::CostFunction {
 public:
  // `rasterizer` must outlive the cost; densification reads its last
  // render's statistics.
  DeviceJointRenderCost(const JointRenderTerms& terms,
                        const Eigen::Vector3d& background,
                        DeviceRasterizer* rasterizer,
                        const EulerOptions& euler = {});

  // Points the cost at frame `frame_index` (its place in the video, for t
  // and p): its camera, its image (device, H W 3 floats, RGB in [0, 1]),
  // with the mask term on its mask (device, H W floats in [0, 1], else
  // nullable), and at a model shape (the host structure, whose vectors and
  // fields must outlive the calls that follow). The arrays must stay alive
  // and unchanged while the cost uses them. Cheap when the structure is
  // unchanged (DeviceFrameComposer::SetStructure).
  void Reset(const Camera& camera, const float* image, const float* mask,
             int frame_index, const LoopStructure& structure);
  // Composes every dynamic Gaussian at this cycle number instead of the
  // frame's own (JointRenderCost::set_cycle_number).
  void set_cycle_number(std::optional<int> cycle_number) {
    cycle_number_ = cycle_number;
  }

  // parameters: the device blocks in layout() order; jacobians: nullptr,
  // or device blocks of the same sizes (a null block is skipped), written
  // with dl/dtheta / r (the dynamic block's zeros with the mask term off).
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Adds (+=) dl/d block into the device gradient blocks (null ones are
  // skipped), without Evaluate's 1 / r. Returns 0.5 r^2 = l + eps / 2.
  double AddLossGradient(double const* const* parameters,
                         double** gradients) const;

  // AddLossGradient in two halves, for a loss across frames between them
  // (JointRenderCost's): RenderForGradient composes, renders and scores
  // the frame, returning 0.5 r^2 and keeping what the backward needs;
  // render() is the image (valid until the next render);
  // BackwardWithImageGradient adds extra_d_rgb (device, H W 3 floats,
  // nullable: another loss's d / d image) to this cost's image gradient
  // (with every term off, the other loss alone) and writes (or, with
  // accumulate, adds) dl/d block into the device gradient blocks.
  double RenderForGradient(double const* const* parameters) const;
  const DeviceImages& render() const { return render_; }
  void BackwardWithImageGradient(double const* const* parameters,
                                 const float* extra_d_rgb, double** gradients,
                                 bool accumulate = false) const;

  const JointBlockLayout& layout() const { return layout_; }
  bool mask_on() const { return image_loss_.mask_on(); }
  // Unweighted terms of the last evaluation (0 for a disabled term).
  double last_photometric() const { return image_loss_.last_photometric(); }
  double last_mask() const { return image_loss_.last_mask(); }
  double last_residual() const { return last_residual_; }
  const EulerStats& last_euler_stats() const {
    return composer_.euler_stats();
  }

 private:
  bool residual_on() const {
    return residual_weight_ != 0 && structure_.residual != nullptr;
  }
  // The model's device view, the dynamic probability attached with the
  // mask term on (RenderedFrameLoss::AttachDynamicChannel).
  DeviceLoopModelView View(double const* const* parameters,
                           bool attach) const;
  // Composes, renders and scores the frame; returns the weighted loss and,
  // with want_grad, keeps the image and D-output gradients.
  double Forward(double const* const* parameters, bool want_grad) const;
  // Adds (+=) dl/d block into every non-null block, from the kept image
  // gradients of the last Forward(want_grad).
  void Backward(double const* const* parameters, double** gradients) const;

  double residual_weight_ = 0;
  Eigen::Vector3d background_;
  DeviceRasterizer* rasterizer_;
  int frame_index_ = 0;
  std::optional<int> cycle_number_;
  LoopStructure structure_;
  JointBlockLayout layout_;
  // Reused between evaluations.
  mutable DeviceFrameComposer composer_;
  mutable DeviceRenderedFrameLoss image_loss_;
  mutable DeviceResidualL2Loss residual_loss_;
  mutable DeviceImages render_;
  mutable DeviceBuffer<double> d_residuals_;
  mutable DeviceGradientArrays splat_grads_;
  mutable bool gradients_ready_ = false;  // the last Forward kept them
  mutable double last_residual_ = 0;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_RENDER_COST_H_
