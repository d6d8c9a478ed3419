#ifndef EULERSPLAT_COSTS_SPLAT_RENDER_COST_H_
#define EULERSPLAT_COSTS_SPLAT_RENDER_COST_H_

#include <ceres/cost_function.h>

#include <memory>
#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"
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

  // The blocks of a GaussianSet in SplatBlock order.
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
