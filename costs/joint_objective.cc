#include "costs/joint_objective.h"

#include <algorithm>

#include "core/base/stage_profile.h"
#include "core/fields/gradient_chunks.h"
#include "costs/splat_render_cost.h"

namespace es {
namespace {

// g *= 0.5 over the chunks `flags` marks (every chunk when null).
void HalveFlaggedChunks(int size, const char* flags, double* g) {
  for (int c = 0; c < NumGradientChunks(size); ++c) {
    if (flags != nullptr && !flags[c]) continue;
    const int end = std::min(size, (c + 1) * kGradientChunk);
    for (int i = c * kGradientChunk; i < end; ++i) g[i] *= 0.5;
  }
}

}  // namespace

JointObjective::JointObjective(const Frame* frame,
                               const LoopStructure& structure,
                               const JointObjectiveOptions& options)
    : options_(options),
      cost_(frame, frame->time_index, structure, options.terms, options.render,
            &rasterizer_, options.euler) {
  if (options_.loop_texture_on()) {
    loop_cost_.emplace(frame, frame->time_index, structure,
                       ImageGradientOnlyTerms(), options.render, &rasterizer_,
                       options_.euler);
    loop_cost_->set_cycle_number(0);
    // The frame just fitted: its Euler chain is reused.
    loop_cost_->RecomposeFrom(&cost_);
    loop_texture_.emplace(options_.loop_texture());
  }
  if (options_.pair_on()) {
    energy_.emplace(options_.water_energy);
    if (options_.texture_on()) texture_.emplace(options_.water_texture);
    pair_cost_.emplace(frame, frame->time_index, structure, options_.terms,
                       options.render, nullptr, options_.euler);
  }
}

const cv::Mat& JointObjective::WaterMask(const Frame& frame) const {
  return options_.water_masks ? frame.mask : no_mask_;
}

double JointObjective::Evaluate(const LoopStructure& structure,
                                double const* const* params, const Frame& frame,
                                const Frame* partner, double water_scale,
                                int64_t iteration, double** gradients,
                                char* const* triplane_chunks,
                                JointObjectiveTerms* terms) {
  const double loss =
      EvaluateFrame(structure, params, frame, partner, water_scale, iteration,
                    gradients, triplane_chunks, terms);
  return loss + AddSceneFlowPrior(params, iteration, gradients,
                                  triplane_chunks, terms);
}

double JointObjective::AddSceneFlowPrior(double const* const* params,
                                         int64_t iteration, double** gradients,
                                         char* const* triplane_chunks,
                                         JointObjectiveTerms* terms) {
  if (!flow_prior_) return 0;
  terms->flow_prior =
      FlowPriorGradient(params, iteration, gradients, triplane_chunks);
  return terms->flow_prior;
}

double JointObjective::EvaluateFrame(const LoopStructure& structure,
                                     double const* const* params,
                                     const Frame& frame, const Frame* partner,
                                     double water_scale, int64_t iteration,
                                     double** gradients,
                                     char* const* triplane_chunks,
                                     JointObjectiveTerms* terms) {
  cost_.Reset(&frame, frame.time_index, structure);
  double loss;
  if (partner != nullptr) {
    CHECK(pair_cost_) << "a partner frame needs a pair term";
    loss = PairLossGradient(structure, params, frame, *partner, water_scale,
                            iteration, gradients, triplane_chunks, terms);
  } else {
    // AddLossGradient adds: the splats' rows are cleared here, the
    // fields' are zero already.
    const std::vector<int32_t>& sizes = cost_.layout().sizes();
    for (int b = 0; b < kNumSplatBlocks; ++b)
      std::fill(gradients[b], gradients[b] + sizes[b], 0.0);
    loss = cost_.AddLossGradient(params, gradients, triplane_chunks);
    terms->photometric = cost_.last_photometric();
    terms->mask = cost_.last_mask();
    terms->residual = cost_.last_residual();
  }
  terms->euler = cost_.last_euler_stats();
  if (loop_cost_ && options_.loop_texture_due(iteration)) {
    loss += LoopTextureGradient(structure, params, frame, water_scale,
                                iteration, gradients, triplane_chunks, terms);
  }
  return loss;
}

void JointObjective::SetSceneFlowPrior(const MotionField& motion,
                                       std::vector<SceneFlowSample> samples,
                                       const FlowPriorOptions& options,
                                       int64_t iterations, uint64_t seed) {
  CHECK_GE(layout().motion_triplane(), 0)
      << "a scene-flow prior needs the motion field";
  UpdateSceneFlowPriorField(motion);
  flow_prior_.emplace(&*prior_field_, std::move(samples), options);
  prior_iterations_ = iterations;
  prior_seed_ = seed;
}

void JointObjective::UpdateSceneFlowPriorField(const MotionField& motion) {
  // Rebuilt in place: flow_prior_ keeps pointing at it.
  prior_field_.emplace(motion);
  prior_field_->SetDisplacementFactor(1.0);
}

double JointObjective::FlowPriorGradient(double const* const* params,
                                         int64_t iteration, double** gradients,
                                         char* const* triplane_chunks) {
  const int v = layout().motion_triplane();
  return flow_prior_->AddLossAndGradient(
      {params[v], params[v + 1]}, iteration, prior_iterations_, prior_seed_,
      {gradients[v], gradients[v + 1],
       triplane_chunks != nullptr ? triplane_chunks[v] : nullptr});
}

double JointObjective::PairLossGradient(const LoopStructure& structure,
                                        double const* const* params,
                                        const Frame& frame, const Frame& other,
                                        double water_scale, int64_t draw,
                                        double** gradients,
                                        char* const* triplane_chunks,
                                        JointObjectiveTerms* terms) {
  pair_cost_->Reset(&other, other.time_index, structure);
  const std::vector<int32_t>& sizes = cost_.layout().sizes();
  // Both backward passes add: the splats' rows are cleared here and
  // averaged below; the fields' rows (zero already) are shared, take the
  // sum of both passes, flagged, and are halved below.
  pair_grad_.resize(kNumSplatBlocks);
  std::vector<double*> pair_gradients(gradients, gradients + sizes.size());
  for (int b = 0; b < kNumSplatBlocks; ++b) {
    std::fill(gradients[b], gradients[b] + sizes[b], 0.0);
    pair_grad_[b].assign(sizes[b], 0.0);
    pair_gradients[b] = pair_grad_[b].data();
  }
  const double loss = cost_.RenderForGradient(params);
  const double pair_loss = pair_cost_->RenderForGradient(params);
  terms->photometric =
      0.5 * (cost_.last_photometric() + pair_cost_->last_photometric());
  terms->mask = 0.5 * (cost_.last_mask() + pair_cost_->last_mask());
  terms->residual = 0.5 * (cost_.last_residual() + pair_cost_->last_residual());

  // The step follows 0.5 (loss + pair_loss + 2 energy): the energy's
  // gradient enters both backward passes at twice its weight and the sum
  // is halved below.
  const bool frame_first = frame.time_index < other.time_index;
  const JointRenderCost& first = frame_first ? cost_ : *pair_cost_;
  const JointRenderCost& second = frame_first ? *pair_cost_ : cost_;
  const Frame& a = frame_first ? frame : other;
  const Frame& b = frame_first ? other : frame;
  energy_grad_a_.assign(first.render().rgb.size(), 0.0);
  energy_grad_b_.assign(second.render().rgb.size(), 0.0);
  const double energy = energy_->Evaluate(
      first.render().rgb.data(), second.render().rgb.data(), a.image, b.image,
      WaterMask(a), WaterMask(b), 2.0 * water_scale, energy_grad_a_.data(),
      energy_grad_b_.data(), &terms->energy);
  const double texture =
      TextureLossGradient(first.render().rgb.data(), second.render().rgb.data(),
                          a, b, water_scale, draw, terms);
  cost_.BackwardWithImageGradient(
      params, frame_first ? energy_grad_a_.data() : energy_grad_b_.data(),
      gradients, /*accumulate=*/true, triplane_chunks);
  pair_cost_->BackwardWithImageGradient(
      params, frame_first ? energy_grad_b_.data() : energy_grad_a_.data(),
      pair_gradients.data(), /*accumulate=*/true, triplane_chunks);
  for (int k = 0; k < kNumSplatBlocks; ++k)
    for (int i = 0; i < sizes[k]; ++i)
      gradients[k][i] = 0.5 * (gradients[k][i] + pair_gradients[k][i]);
  // The fields' sum: the triplanes' flagged chunks, the MLPs whole.
  for (size_t b = kNumSplatBlocks; b < sizes.size(); ++b) {
    // nullptr: an MLP, or no flags kept.
    const char* flags = triplane_chunks ? triplane_chunks[b] : nullptr;
    HalveFlaggedChunks(sizes[b], flags, gradients[b]);
  }
  return 0.5 * (loss + pair_loss + energy + texture);
}

double JointObjective::TextureLossGradient(const double* render_a,
                                           const double* render_b,
                                           const Frame& a, const Frame& b,
                                           double water_scale, int64_t draw,
                                           JointObjectiveTerms* terms) {
  if (!texture_) return 0;
  // Each frame's distance at its full weight: the pair's sum is halved,
  // so the term is the two frames' mean.
  const double sum =
      texture_->Evaluate(render_a, a.image, WaterMask(a), water_scale,
                         PairTextureDraw(draw, 0), energy_grad_a_.data()) +
      texture_->Evaluate(render_b, b.image, WaterMask(b), water_scale,
                         PairTextureDraw(draw, 1), energy_grad_b_.data());
  terms->texture =
      UnrampedMean(sum, 2, water_scale, options_.water_texture.weight);
  return sum;
}

double JointObjective::LoopTextureGradient(
    const LoopStructure& structure, double const* const* params,
    const Frame& frame, double water_scale, int64_t draw, double** gradients,
    char* const* triplane_chunks, JointObjectiveTerms* terms) {
  ScopedPass pass(Pass::kLoopTexture);
  loop_cost_->Reset(&frame, frame.time_index, structure);
  loop_cost_->RenderForGradient(params);
  loop_grad_.assign(loop_cost_->render().rgb.size(), 0.0);
  const double loss = loop_texture_->Evaluate(
      loop_cost_->render().rgb.data(), frame.image, WaterMask(frame),
      water_scale, LoopTextureDraw(draw), loop_grad_.data());
  terms->loop_texture =
      UnrampedMean(loss, 1, water_scale, options_.loop_texture_step_weight());
  loop_cost_->BackwardWithImageGradient(params, loop_grad_.data(), gradients,
                                        /*accumulate=*/true, triplane_chunks);
  return loss;
}

double JointObjective::FitGradient(const LoopStructure& structure,
                                   double const* const* params,
                                   const Frame& frame, double** gradients) {
  cost_.Reset(&frame, frame.time_index, structure);
  return cost_.LossGradient(params, gradients);
}

}  // namespace es
