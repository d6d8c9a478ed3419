#ifndef EULERSPLAT_COSTS_JOINT_OBJECTIVE_H_
#define EULERSPLAT_COSTS_JOINT_OBJECTIVE_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/fields/motion_field.h"
#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"
#include "costs/joint_objective_options.h"
#include "costs/joint_render_cost.h"
#include "costs/scene_flow_prior.h"
#include "costs/water_energy_loss.h"
#include "costs/water_texture_loss.h"

namespace es {

// Stage 3's loss and gradient for one sampled frame, the one objective the
// CPU trainer steps on (its device twin: cuda::DeviceJointObjective):
//   - frame i alone: its JointRenderCost (photometric, mask BCE, D's L2);
//   - with a partner (the frame's neighbour in the video, when a pair term
//     is on): the mean of both frames' fits plus WaterEnergyLoss across
//     them and the mean of both frames' WaterTextureLoss,
//       0.5 (fit_i + fit_j + 2 energy + texture_i + texture_j);
//   - plus the loop texture term of frame i (composed at cycle number 0)
//     on the iterations its interval picks;
//   - plus, once set, Stage 2's scene-flow prior on V (SceneFlowPrior).
// The water losses are scaled by the caller's ramp. Reuses its buffers:
// not thread-safe.
class JointObjective {
 public:
  // `frame` (any training frame, the costs' first) and the structure's
  // data must outlive the objective until the first Evaluate repoints it.
  JointObjective(const Frame* frame, const LoopStructure& structure,
                 const JointObjectiveOptions& options);

  const JointObjectiveOptions& options() const { return options_; }
  const JointBlockLayout& layout() const { return cost_.layout(); }

  // From now on Evaluate adds Stage 2's scene-flow prior on V (the
  // layout's motion blocks), its weight decaying over a run of
  // `iterations` seeded `seed`. `motion` gives V's structure (box,
  // layout); the prior scores V itself, not its warmed-up displacement.
  void SetSceneFlowPrior(const MotionField& motion,
                         std::vector<SceneFlowSample> samples,
                         const FlowPriorOptions& options, int64_t iterations,
                         uint64_t seed);
  // V's structure changed (a restored checkpoint's box): the prior follows.
  void UpdateSceneFlowPriorField(const MotionField& motion);
  bool has_scene_flow_prior() const { return flow_prior_.has_value(); }

  // The loss of `frame` (and `partner`, nullable: no pair terms) of the
  // model `structure` with the JointBlockLayout blocks `params` at the
  // run's iteration `iteration` (it picks the texture terms' directions
  // and the prior's batch and weight); `water_scale` ramps the water
  // losses. The gradient goes into `gradients` (layout order): the
  // splats' rows are overwritten, the fields' added to (+=; the caller
  // keeps them zero between steps), flagging written chunks in
  // `triplane_chunks` (nullable, as JointRenderCost::AddLossGradient).
  // `terms` receives the unweighted terms.
  double Evaluate(const LoopStructure& structure, double const* const* params,
                  const Frame& frame, const Frame* partner, double water_scale,
                  int64_t iteration, double** gradients,
                  char* const* triplane_chunks, JointObjectiveTerms* terms);
  // Evaluate's two parts: the frame's terms (all but the prior), and the
  // prior added to the loss it returns and to `gradients` (terms->
  // flow_prior set; 0 without a prior). A batch of frames sums the first
  // over its frames and adds the second once.
  double EvaluateFrame(const LoopStructure& structure,
                       double const* const* params, const Frame& frame,
                       const Frame* partner, double water_scale,
                       int64_t iteration, double** gradients,
                       char* const* triplane_chunks,
                       JointObjectiveTerms* terms);
  double AddSceneFlowPrior(double const* const* params, int64_t iteration,
                           double** gradients, char* const* triplane_chunks,
                           JointObjectiveTerms* terms);

  // Frame `frame`'s fit alone, its gradient written into `gradients`
  // (every non-null row); rasterizer() then holds its render's
  // statistics (water densification's ranking).
  double FitGradient(const LoopStructure& structure,
                     double const* const* params, const Frame& frame,
                     double** gradients);
  const Rasterizer& rasterizer() const { return rasterizer_; }

 private:
  double PairLossGradient(const LoopStructure& structure,
                          double const* const* params, const Frame& frame,
                          const Frame& other, double water_scale, int64_t draw,
                          double** gradients, char* const* triplane_chunks,
                          JointObjectiveTerms* terms);
  // The pair's texture term (a before b in the video), its gradient added
  // to the energy's image gradients; 0 when off.
  double TextureLossGradient(const double* render_a, const double* render_b,
                             const Frame& a, const Frame& b, double water_scale,
                             int64_t draw, JointObjectiveTerms* terms);
  double LoopTextureGradient(const LoopStructure& structure,
                             double const* const* params, const Frame& frame,
                             double water_scale, int64_t draw,
                             double** gradients, char* const* triplane_chunks,
                             JointObjectiveTerms* terms);
  double FlowPriorGradient(double const* const* params, int64_t iteration,
                           double** gradients, char* const* triplane_chunks);
  const cv::Mat& WaterMask(const Frame& frame) const;

  JointObjectiveOptions options_;
  Rasterizer rasterizer_;
  JointRenderCost cost_;
  // The pair terms: the partner's cost (its own rasterizer: both renders
  // are kept until both backward passes), its splat gradient rows, the
  // water losses and their image gradients.
  std::optional<JointRenderCost> pair_cost_;
  std::vector<std::vector<double>> pair_grad_;
  std::optional<WaterEnergyLoss> energy_;
  std::optional<WaterTextureLoss> texture_;
  std::vector<double> energy_grad_a_, energy_grad_b_;
  // The loop texture term: the frame as the loop plays it (rendered on
  // rasterizer_ after cost_'s backward pass), its loss and image gradient.
  std::optional<JointRenderCost> loop_cost_;
  std::optional<WaterTextureLoss> loop_texture_;
  std::vector<double> loop_grad_;
  cv::Mat no_mask_;
  // The scene-flow prior, on a copy of V at full displacement.
  std::optional<MotionField> prior_field_;
  std::optional<SceneFlowPrior> flow_prior_;
  int64_t prior_iterations_ = 0;
  uint64_t prior_seed_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_JOINT_OBJECTIVE_H_
