#ifndef EULERSPLAT_COSTS_JOINT_RENDER_COST_H_
#define EULERSPLAT_COSTS_JOINT_RENDER_COST_H_

#include <memory>
#include <optional>
#include <vector>

#include <ceres/cost_function.h>

#include "core/io/scene.h"
#include "core/loop/frame_composer.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"
#include "costs/rendered_frame_loss.h"
#include "costs/residual_l2_cost.h"

namespace es {

// Which terms a JointRenderCost sums: the image terms of every render cost
// plus the L2 term on D's outputs; a zero weight turns a term off.
struct JointRenderTerms : ImageLossTerms {
  double residual_weight = 0.0;  // ResidualL2Loss of D's outputs
};

// Parameter block order: the six GaussianSet arrays (SplatBlock order of
// costs/splat_render_cost.h), then V's triplane and MLP if the structure
// has V, then D's triplane and MLP if it has D.
class JointBlockLayout {
 public:
  explicit JointBlockLayout(const LoopStructure& s);
  int num_blocks() const { return static_cast<int>(sizes_.size()); }
  const std::vector<int32_t>& sizes() const { return sizes_; }
  int motion_triplane() const { return motion_; }    // -1 if absent
  int motion_mlp() const { return motion_ < 0 ? -1 : motion_ + 1; }
  int residual_triplane() const { return residual_; }  // -1 if absent
  int residual_mlp() const { return residual_ < 0 ? -1 : residual_ + 1; }

  // A field's two blocks of `parameters` (layout order), nulls when the
  // layout has no such field.
  FieldParams MotionParams(double const* const* parameters) const;
  FieldParams ResidualParams(double const* const* parameters) const;
  // A field's two blocks of `gradients`, with the triplane's chunk flags
  // from `triplane_chunks` (nullable: none); nulls when it is absent.
  FieldGradients MotionGradients(double* const* gradients,
                                 char* const* triplane_chunks) const;
  FieldGradients ResidualGradients(double* const* gradients,
                                   char* const* triplane_chunks) const;

 private:
  std::vector<int32_t> sizes_;
  int motion_ = -1, residual_ = -1;
};

// The model's blocks in JointBlockLayout order (its own arrays).
std::vector<double*> JointBlocks(LoopModel* model);

// The joint-training loss of one frame i: the looping model is composed at
// frame i (Alg. 1 advection of the dynamic Gaussians by V to their cycle
// index, plus D's position, opacity and SH offsets;
// core/loop/frame_composer.h), rendered once, and scored by every enabled
// term (RenderedFrameLoss plus D's L2),
//   l = w_p photometric + w_m BCE(dynamic channel, mask) + w_r D L2,
// exposed as one residual sqrt(2 l + eps) (costs/scalar_loss.h). The
// gradient flows through the rasterizer, D and the whole Euler chain to the
// canonical splats, V's and D's parameters. Evaluate reuses internal
// buffers: not thread-safe.
class JointRenderCost : public ceres::CostFunction {
 public:
  // frame, the structure's data and rasterizer (if given) must outlive the
  // cost. frame_index is i (its place in the video, for t and p).
  JointRenderCost(const Frame* frame, int frame_index,
                  const LoopStructure& structure,
                  const JointRenderTerms& terms, const RenderOptions& options,
                  Rasterizer* rasterizer = nullptr,
                  const EulerOptions& euler = {});

  // Points the cost at another frame or model shape, keeping its buffers.
  void Reset(const Frame* frame, int frame_index,
             const LoopStructure& structure);
  // Composes every dynamic Gaussian at this cycle number instead of the
  // frame's own (FrameComposer::Compose): 0 scores frame i of the loop as
  // it plays; nullopt (the default) the frame as training fits it.
  void set_cycle_number(std::optional<int> cycle_number) {
    cycle_number_ = cycle_number;
  }

  // From now on this cost composes through `source`'s composer
  // (FrameComposer::Recompose at its cycle number, which must be set):
  // the frame `source` composed last, its Euler chain reused. For a cost
  // of the same frame and parameters whose forward pass follows
  // `source`'s backward pass (the loop texture's render of the frame
  // just fitted); `source` must outlive it.
  void RecomposeFrom(const JointRenderCost* source);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The trainer's path: d loss / d block straight into `gradients` (one
  // buffer per block, sized like it; null skips a block), without the
  // residual's 1 / r that Evaluate applies and the caller would undo (two
  // passes over the fields' parameters). Returns 0.5 r^2 = l + eps / 2, as
  // EvaluateScalarLossGradient.
  double LossGradient(double const* const* parameters,
                      double** gradients) const;
  // LossGradient that adds (+=) d loss / d block to the rows instead, so a
  // caller that keeps them zero between calls (the trainer, whose field
  // gradients touch few texels) need not clear whole field-sized rows.
  // triplane_chunks (nullable) is indexed like gradients: for the fields'
  // triplane blocks, chunk flags (core/fields/gradient_chunks.h) set where
  // this call writes, so the caller need not scan the whole block; other
  // entries are ignored and may be null.
  double AddLossGradient(double const* const* parameters, double** gradients,
                         char* const* triplane_chunks = nullptr) const;

  // LossGradient in two halves, for a loss across frames between them:
  // RenderForGradient composes, renders and scores the frame (returning
  // the loss as LossGradient does) and keeps what the backward pass needs;
  // render() is the image; BackwardWithImageGradient adds `extra_d_rgb`
  // (nullable, H x W x 3: the other loss's d / d image) to this cost's
  // image gradient and writes d loss / d block into `gradients` (with
  // every term off, the other loss alone).
  double RenderForGradient(double const* const* parameters) const;
  const RenderResult& render() const { return render_; }
  // With accumulate it adds (+=) into the rows, with triplane_chunks as
  // in AddLossGradient.
  void BackwardWithImageGradient(double const* const* parameters,
                                 const double* extra_d_rgb, double** gradients,
                                 bool accumulate = false,
                                 char* const* triplane_chunks = nullptr) const;

  const JointBlockLayout& layout() const { return layout_; }
  // Unweighted terms of the last Evaluate (0 for a disabled term).
  double last_photometric() const { return image_loss_.last_photometric(); }
  double last_mask() const { return image_loss_.last_mask(); }
  double last_residual() const { return last_residual_; }
  const EulerStats& last_euler_stats() const {
    return composer().euler_stats();
  }

 private:
  FrameComposer& composer() const {
    return source_ != nullptr ? source_->composer_ : composer_;
  }
  LoopModelView View(double const* const* parameters) const;
  // View with the dynamic-probability channel attached for the mask loss.
  LoopModelView AttachedView(double const* const* parameters) const;
  // 0.5 r^2 of the frame's residual r, rendered keeping what Backward needs.
  double HalfSquaredLoss(const LoopModelView& model) const;
  bool residual_on() const {
    return residual_weight_ != 0 && structure_.residual != nullptr;
  }
  // Composes, renders and scores the frame; returns the weighted loss and
  // keeps what Backward needs when want_grad.
  double Forward(const LoopModelView& model, bool want_grad) const;
  // Writes (or, with accumulate, adds) d loss / d block into every
  // non-null gradient row.
  // triplane_chunks as in AddLossGradient.
  void Backward(const LoopModelView& model, double** gradients,
                bool accumulate = false,
                char* const* triplane_chunks = nullptr) const;

  const Frame* frame_ = nullptr;
  int frame_index_ = 0;
  std::optional<int> cycle_number_;
  LoopStructure structure_;
  JointBlockLayout layout_;
  double residual_weight_ = 0;
  RenderOptions options_;
  std::unique_ptr<Rasterizer> owned_rasterizer_;
  Rasterizer* rasterizer_;
  // Reused between evaluations.
  mutable RenderedFrameLoss image_loss_;
  mutable FrameComposer composer_;
  const JointRenderCost* source_ = nullptr;  // RecomposeFrom's
  mutable std::vector<double> d_residuals_;
  mutable RenderResult render_;
  mutable SplatGradients grads_;
  mutable std::vector<double> dynamic_logit_grad_;
  mutable double last_residual_ = 0;
};

// Single-term costs (weight 1; weight them with ceres::ScaledLoss).
ceres::CostFunction* CreateJointPhotometricCost(
    const Frame* frame, int frame_index, const LoopStructure& structure,
    double ssim_weight, const RenderOptions& options);
ceres::CostFunction* CreateJointMaskBceCost(const Frame* frame,
                                            int frame_index,
                                            const LoopStructure& structure,
                                            const RenderOptions& options);

}  // namespace es

#endif  // EULERSPLAT_COSTS_JOINT_RENDER_COST_H_
