#ifndef EULERSPLAT_CORE_LOOP_FRAME_COMPOSER_H_
#define EULERSPLAT_CORE_LOOP_FRAME_COMPOSER_H_

#include <optional>
#include <vector>

#include "core/fields/field_gradient_buffer.h"
#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/loop/euler_chain.h"
#include "core/loop/loop_model.h"
#include "core/render/splat_gradient_pointers.h"
#include "core/render/rasterizer.h"

namespace es {

// Read-only view of a looping model to compose: its structure
// (core/loop/loop_model.h) plus pointers to its parameter values, which may
// be the model's own arrays or the blocks Ceres hands a cost function.
struct LoopModelView {
  LoopStructure structure;  // no motion field: dynamic ones don't flow;
                            // no residual field: no residual offsets
  SplatView canonical;      // all Gaussians; extra is passed through
  FieldParams motion_params;    // V's, when structure.motion is set
  FieldParams residual_params;  // D's, when structure.residual is set

  // View of a model with its own parameter arrays (no extra channel).
  static LoopModelView Of(const LoopModel& model);
};

// Gradient accumulators (+=) for the blocks of a LoopModelView, sized like
// them; nullptr skips a block. The device composer takes it with device
// pointers.
struct LoopModelGradients : SplatGradientPointers {
  FieldGradients motion;
  FieldGradients residual;
};

// Builds the splats to render at a frame from a looping model. Static
// Gaussians are copied unchanged. Dynamic Gaussian k (canonical index
// dynamic_index[k], start time t0_k) at frame i has cycle index
// t = CycleIndex(i, t0_k, L) and cycle number p = CycleNumber(i, t0_k, L):
//   position = EulerChain(x0, t steps of V)  + D(x0, t, p)[position]
//   opacity  = canonical logit               + D(x0, t, p)[opacity]
//   sh[k']   = canonical sh[k']              + D(x0, t, p)[sh k'],
//              for k' < min(K, 16) (K = the model's SH coefficients)
// with the V term x0 when there is no motion field and no D terms when
// there is no residual field. V and D are evaluated on the dynamic
// Gaussians only, in batches: the dynamic Gaussians are cut into shares of
// about equal field work (Euler steps and D), one per OpenMP thread, each
// advected and evaluated by its thread alone, forward and backward, so a
// pass is one parallel region; the shares' parameter gradients are summed
// in share order at the end (for a given thread count the result does not
// depend on scheduling). Each share after the first keeps a gradient
// buffer the size of V's and of D's parameters (about 11 MB at the
// default 128^2 planes), allocated on its first Backward. Owns the composed
// arrays; the returned view (log-scales, quaternions and extra point at the
// canonical arrays) stays valid until the next Compose* call. Not thread-safe.
class FrameComposer {
 public:
  explicit FrameComposer(const EulerOptions& euler_options = {});

  // Training / evaluation: frame i, Alg. 1 from the canonical positions,
  // t and p from the true frame index. Keeps what Backward needs. With
  // `cycle_number`, every dynamic Gaussian takes that p instead: frame i
  // of the loop as Alg. 2 plays it (p = 0), with its gradient.
  const SplatView& Compose(const LoopModelView& model, int frame,
                           std::optional<int> cycle_number = std::nullopt);

  // The last Compose's frame again with every dynamic Gaussian at cycle
  // number `cycle_number`: the Euler chain's positions (and its state,
  // which Backward runs through again) are reused, only D is evaluated
  // anew. Equals Compose(model, frame, cycle_number) of the same frame
  // bit for bit, provided V's parameters and the canonical means are
  // those of the last Compose (the loop texture's render of the frame
  // just fitted). Keeps what Backward needs.
  const SplatView& Recompose(const LoopModelView& model, int cycle_number);

  // Animation (Alg. 2): dynamic positions already advected elsewhere
  // (num_dynamic x 3, in dynamic order, e.g. LoopAnimator::positions()),
  // their cycle indices, and one cycle number for all (0 at inference).
  // D is still evaluated at the canonical positions. Forward only.
  const SplatView& ComposeAdvected(const LoopModelView& model,
                                   const double* positions,
                                   const int* cycle_indices,
                                   int cycle_number);

  // Backward of the last Compose (same model view): maps d loss / d
  // composed splats to the canonical blocks (the dynamic positions through
  // both the Euler chain and D's dependence on x0), V's parameters (through
  // EulerChain::Backward) and D's parameters (through
  // ResidualField::Backward). d_residuals (num_dynamic x kResidualDim,
  // nullable) is added to the gradient of D's outputs, for losses on them
  // (e.g. the residual L2 term).
  void Backward(const LoopModelView& model, const SplatGradients& grads,
                const double* d_residuals, const LoopModelGradients& out);

  // D's outputs of the last Compose* (num_dynamic x kResidualDim; empty
  // without a residual field) and the cycle indices / numbers used.
  const std::vector<double>& residuals() const { return residuals_; }
  const std::vector<int>& cycle_indices() const { return cycle_index_; }
  const std::vector<int>& cycle_numbers() const { return cycle_number_; }
  // Euler-chain counts of the last Compose.
  const EulerStats& euler_stats() const { return euler_stats_; }
  // Shares the last Compose* cut the dynamic Gaussians into (1 when it
  // ran on one thread).
  int num_shares() const { return num_shares_; }
  // At most this many shares (0: one per OpenMP thread), for tests that
  // compare a split run with a one-share run.
  void set_max_shares(int max_shares) { max_shares_ = max_shares; }

 private:
  // A contiguous range of the dynamic Gaussians (dynamic order) that one
  // thread advects and evaluates D for, with its own workspaces.
  struct Share {
    int begin = 0, end = 0;
    std::optional<EulerChain> chain;
    const MotionField* chain_field = nullptr;
    FieldWorkspace residual_ws;
    EulerStats stats;
    // Gradients of the shares after the first (the first writes into the
    // caller's buffers).
    FieldGradientBuffer motion_grads, residual_grads;
  };
  // Cuts the m dynamic Gaussians into shares (num_shares_) by their field
  // work: `steps` Euler steps each when advect, plus one D evaluation.
  void PlanShares(const LoopStructure& s, int m, bool advect);
  // Forward of V (when advect) and D on every share into positions_ and
  // residuals_.
  void EvaluateFields(const LoopModelView& model, bool advect);
  // D on share g (its canonical positions, cycle indices and numbers)
  // into its rows of residuals_; on every share, in parallel.
  void ResidualOnShare(const LoopModelView& model, int g);
  void EvaluateResidual(const LoopModelView& model);
  // run(g) for every share, one thread each.
  template <typename Run>
  void RunShares(const Run& run);
  // The composed arrays from positions_ and residuals_.
  const SplatView& Assemble(const LoopModelView& model);
  // D's and (when the last Compose advected) V's backward on every share,
  // from d_positions_ and d_residuals_, adding dL/dx0 into d_x0_.
  void FieldsBackward(const LoopModelView& model,
                      const LoopModelGradients& out);

  EulerOptions euler_options_;
  std::vector<Share> shares_;
  std::vector<FieldGradientBuffer*> gradient_buffers_;
  int num_shares_ = 0;
  int max_shares_ = 0;
  bool advected_ = false;  // the last Compose* ran the Euler chain
  EulerStats euler_stats_;
  bool backward_ready_ = false;  // the last Compose* was Compose
  std::vector<double> canonical_, positions_, residuals_;
  std::vector<int> cycle_index_, cycle_number_;
  std::vector<double> means_, opacity_logits_, sh_;
  std::vector<double> d_positions_, d_residuals_, d_x0_;
  SplatView view_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_FRAME_COMPOSER_H_
