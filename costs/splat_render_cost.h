#ifndef EULERSPLAT_COSTS_SPLAT_RENDER_COST_H_
#define EULERSPLAT_COSTS_SPLAT_RENDER_COST_H_

#include <ceres/cost_function.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
#include "core/render/splat_gradient_pointers.h"
#include "costs/rendered_frame_loss.h"

namespace es {

// The parameter blocks, in order: the GaussianSet arrays.
enum SplatBlock {
  kMeansBlock = 0,
  kLogScalesBlock,
  kQuatsBlock,
  kOpacityBlock,
  kShBlock,
  kDynamicBlock,
  kNumSplatBlocks
};
// The splat costs (here, costs/joint_render_cost.h and their device twins)
// take every GaussianSet array as a block, in kGaussianArrays order: an
// array added to the table needs its block here and its Jacobian in their
// Evaluate (through SplatView if the renderer reads it, else zero).
static_assert(int{kMeansBlock} == kMeansArray &&
                  int{kLogScalesBlock} == kLogScalesArray &&
                  int{kQuatsBlock} == kQuatsArray &&
                  int{kOpacityBlock} == kOpacityArray &&
                  int{kShBlock} == kShArray &&
                  int{kDynamicBlock} == kDynamicArray &&
                  int{kNumSplatBlocks} == kNumGaussianArrays,
              "the splat blocks are the GaussianSet arrays, in table order");

// The sizes of the splat blocks of `count` Gaussians of `sh_degree`.
std::vector<int32_t> SplatBlockSizes(int count, int sh_degree);

// Points a view of the rendered arrays (on the host or the device alike) at
// the splat blocks: where a rendered array's block goes, once for every
// cost.
inline void ViewSplatBlocks(double const* const* blocks, int count,
                            int sh_degree, SplatView* view) {
  view->count = count;
  view->sh_degree = sh_degree;
  view->means = blocks[kMeansBlock];
  view->log_scales = blocks[kLogScalesBlock];
  view->quats = blocks[kQuatsBlock];
  view->opacity_logits = blocks[kOpacityBlock];
  view->sh = blocks[kShBlock];
}

// The same for the arrays a backward writes (LoopModelGradients,
// DeviceSplatGradients): the rendered blocks' rows of `jacobians`.
inline void PointAtSplatJacobians(double* const* jacobians,
                                  SplatGradientPointers* out) {
  out->means = jacobians[kMeansBlock];
  out->log_scales = jacobians[kLogScalesBlock];
  out->quats = jacobians[kQuatsBlock];
  out->opacity_logits = jacobians[kOpacityBlock];
  out->sh = jacobians[kShBlock];
}

// Renders one frame from the splat parameter blocks once and scores it with
// every enabled term (RenderedFrameLoss), sharing one rasterizer Forward and
// one Backward, exposed as one residual sqrt(2 l + eps)
// (costs/scalar_loss.h). Blocks a term does not touch get a zero Jacobian.
// Evaluate reuses internal buffers: not thread-safe.
class SplatRenderCost : public ceres::CostFunction {
 public:
  // `frame` (and `rasterizer`, if given) must outlive the cost; without a
  // rasterizer the cost owns one.
  SplatRenderCost(const Frame* frame, int count, int sh_degree,
                  const ImageLossTerms& terms, const RenderOptions& options,
                  Rasterizer* rasterizer = nullptr);

  // Points the cost at another frame / model size, keeping its buffers.
  void Reset(const Frame* frame, int count, int sh_degree);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The unweighted terms of the last Evaluate (0 for a disabled term).
  double last_photometric() const { return loss_.last_photometric(); }
  double last_mask() const { return loss_.last_mask(); }

  // The blocks of a GaussianSet in SplatBlock (kGaussianArrays) order.
  static std::vector<double*> Blocks(GaussianSet* g);

 private:
  const Frame* frame_ = nullptr;
  int count_ = 0;
  int sh_degree_ = 0;
  RenderOptions options_;
  std::unique_ptr<Rasterizer> owned_rasterizer_;
  Rasterizer* rasterizer_;
  // Reused between evaluations.
  mutable RenderedFrameLoss loss_;
  mutable RenderResult render_;
  mutable SplatGradients grads_;
};

// Single-term costs (weight 1; weight them with ceres::ScaledLoss).
ceres::CostFunction* CreatePhotometricCost(const Frame* frame, int count,
                                           int sh_degree, double ssim_weight,
                                           const RenderOptions& options);
ceres::CostFunction* CreateMaskBceCost(const Frame* frame, int count,
                                       int sh_degree,
                                       const RenderOptions& options);

}  // namespace es

#endif  // EULERSPLAT_COSTS_SPLAT_RENDER_COST_H_
