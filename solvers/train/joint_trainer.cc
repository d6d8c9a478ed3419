#include "solvers/train/joint_trainer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glog/logging.h>

#include "core/fields/gradient_chunks.h"
#include "core/base/input_error.h"
#include "core/loop/cycle_time.h"
#include "core/loop/frame_composer.h"
#include "core/model/dynamic_set.h"
#include "core/base/stage_profile.h"
#include "costs/splat_render_cost.h"
#include "core/base/rng_state.h"
#include "solvers/optim/lr_schedule.h"
#include "solvers/train/densify.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/water_particles.h"

namespace es {
JointTrainer::JointTrainer(const std::vector<Frame>* frames,
                           std::vector<int> train,
                           const JointTrainerOptions& options,
                           GaussianSet initial,
                           std::optional<MotionField> motion)
    : frames_(frames),
      train_(std::move(train)),
      options_(options),
      use_masks_(options.mask_weight > 0 && AllHaveMasks(*frames, train_)),
      extent_(CameraExtent(*frames, train_)),
      sampler_(train_, options.seed),
      rng_(options.seed + 1),
      guard_("Stage 3 training", options.max_nonfinite_steps) {
  model_ = InitialLoopModel(options_, static_cast<int>(frames_->size()),
                            std::move(initial), std::move(motion), &rng_);
  UpdateScaleBounds();
  initial_dynamic_ = model_.num_dynamic();
  guarded_ = GuardedJointBlocks(options_, model_, extent_);
  adam_.Reset(model_.gaussians);
  for (std::vector<double>* block : FieldParamBlocks(&model_)) {
    field_adam_.emplace_back(static_cast<int>(block->size()));
    field_grad_.emplace_back(block->size(), 0.0);
  }
  cost_.emplace(&(*frames_)[train_.at(0)],
                (*frames_)[train_.at(0)].time_index,
                LoopStructure::Of(model_),
                JointLossTerms(options_, use_masks_),
                render_options(), &rasterizer_, options_.euler);
  energy_masks_ = WaterLossOn(options_) && AllHaveMasks(*frames_, train_);
  if (LoopTextureOn(options_)) {
    loop_cost_.emplace(&(*frames_)[train_.at(0)],
                       (*frames_)[train_.at(0)].time_index,
                       LoopStructure::Of(model_), ImageGradientOnlyTerms(),
                       render_options(), &rasterizer_, options_.euler);
    loop_cost_->set_cycle_number(0);
    loop_texture_.emplace(LoopTextureOptions(options_));
  }
  if (PairLossOn(options_)) {
    partner_ = TrainingNeighbours(*frames_, train_);
    energy_.emplace(options_.water_energy);
    if (WaterTextureOn(options_)) texture_.emplace(options_.water_texture);
    // Its own rasterizer: both renders are kept until both backward passes.
    pair_cost_.emplace(&(*frames_)[train_.at(0)],
                       (*frames_)[train_.at(0)].time_index,
                       LoopStructure::Of(model_),
                       JointLossTerms(options_, use_masks_),
                       render_options(), nullptr, options_.euler);
  }
  ApplyMotionRamp(options_, iteration_, &model_);
}

void JointTrainer::SetSceneFlowPrior(std::vector<SceneFlowSample> samples) {
  CHECK(model_.motion) << "a scene-flow prior needs the motion field";
  // The prior scores V itself, not its warmed-up displacement.
  prior_field_.emplace(*model_.motion);
  prior_field_->SetDisplacementFactor(1.0);
  flow_prior_.emplace(&*prior_field_, std::move(samples),
                      options_.flow_prior);
}

RenderOptions JointTrainer::render_options() const {
  return JointRenderOptions(options_);
}

std::vector<char*> JointTrainer::TriplaneChunkFlags() {
  const JointBlockLayout& layout = cost_->layout();
  std::vector<char*> chunks(layout.num_blocks(), nullptr);
  // Field blocks: V's triplane and MLP, then D's.
  if (layout.motion_triplane() >= 0)
    chunks[layout.motion_triplane()] = field_adam_[0].chunk_flags();
  if (layout.residual_triplane() >= 0) {
    chunks[layout.residual_triplane()] =
        field_adam_[model_.motion ? 2 : 0].chunk_flags();
  }
  return chunks;
}

void JointTrainer::RefreshDynamicSet() {
  FollowDynamicSet(options_,
                   DynamicSet(model_.gaussians, options_.dynamic_threshold),
                   &rng_, &model_);
  UpdateScaleBounds();
}

void JointTrainer::UpdateScaleBounds() {
  if (options_.max_dynamic_pixels <= 0) return;
  dynamic_max_scale_ =
      PixelSizeInWorld(model_.gaussians, model_.dynamic_index, *frames_,
                       train_, options_.max_dynamic_pixels);
}

void JointTrainer::ClampDynamicScales() {
  if (options_.max_dynamic_pixels <= 0) return;
  ClampScales(model_.dynamic_index, dynamic_max_scale_, &model_.gaussians);
}

JointIterationStats JointTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (DynamicSetRefreshDue(options_, iteration_)) RefreshDynamicSet();
  JointIterationStats out;
  out.frame = sampler_.Next();
  out.num_dynamic = model_.num_dynamic();
  const int n = model_.gaussians.size();
  if (grad_.size() != n || grad_.sh_degree != model_.gaussians.sh_degree)
    grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  const Frame& frame = (*frames_)[out.frame];
  cost_->Reset(&frame, frame.time_index, LoopStructure::Of(model_));
  const int partner = PairLossOn(options_) ? partner_[out.frame] : -1;
  if (partner >= 0) {
    out.loss = PairLossGradient(frame, partner, &out);
  } else {
    std::vector<double*> params = JointBlocks(&model_);
    std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
    // AddLossGradient adds: the splats' rows are cleared here, the
    // fields' are zero already.
    const JointBlockLayout& layout = cost_->layout();
    const std::vector<int32_t>& sizes = layout.sizes();
    for (size_t b = 0; b < gradients.size(); ++b)
      std::fill(gradients[b], gradients[b] + sizes[b], 0.0);
    for (std::vector<double>& g : field_grad_) gradients.push_back(g.data());
    const std::vector<char*> chunks = TriplaneChunkFlags();
    out.loss = cost_->AddLossGradient(params.data(), gradients.data(),
                                      chunks.data());
    out.photometric = cost_->last_photometric();
    out.mask = cost_->last_mask();
    out.residual = cost_->last_residual();
  }
  out.euler = cost_->last_euler_stats();
  if (loop_cost_) out.loss += LoopTextureGradient(frame, &out);
  if (flow_prior_) {
    // V's blocks come first among the field gradients.
    out.flow_prior = flow_prior_->AddLossAndGradient(
        model_.motion->params(), iteration_, options_.iterations,
        options_.seed,
        {field_grad_[0].data(), field_grad_[1].data(),
         field_adam_[0].chunk_flags()});
    out.loss += out.flow_prior;
  }
  // Every writer of the triplanes' gradients (the costs, the flow prior)
  // flagged the chunks it wrote into their SparseAdam's flags, so only
  // those are read; the MLPs' small blocks are scanned whole.
  bool finite = std::isfinite(out.loss) && AllFinite(grad_);
  for (size_t b = 0; b < field_grad_.size(); ++b) {
    SparseAdam& adam = field_adam_[b];
    const bool triplane = b % 2 == 0;
    finite = (triplane ? adam.ScanFlagged(field_grad_[b].data())
                       : adam.ScanGradient(field_grad_[b].data())) &&
             finite;
  }
  if (!guard_.Accept(iteration_ + 1, finite)) {
    for (size_t b = 0; b < field_grad_.size(); ++b)
      field_adam_[b].ClearGradient(field_grad_[b].data());
    out.skipped = true;
    ++iteration_;
    ApplyMotionRamp(options_, iteration_, &model_);
    return out;
  }

  adam_.Step(ScheduledSplatRates(options_.splat_lr, extent_, iteration_,
                                 options_.iterations, use_masks_),
             grad_, &model_.gaussians);
  ClampDynamicScales();
  ++field_step_;
  const std::vector<double> lr =
      FieldLearningRates(options_, iteration_, model_);
  std::vector<std::vector<double>*> blocks = FieldParamBlocks(&model_);
  for (size_t b = 0; b < blocks.size(); ++b) {
    field_adam_[b].Step(field_step_, lr[b], field_grad_[b].data(),
                        blocks[b]->data());
  }
  // Every value, not only those the step changed: a block's largest
  // magnitude is what tells a runaway learning rate.
  std::vector<double> magnitudes = SplatMagnitudes(model_.gaussians);
  for (const std::vector<double>* block : blocks)
    magnitudes.push_back(MaxMagnitude(*block));
  ++iteration_;
  ApplyMotionRamp(options_, iteration_, &model_);
  guard_.CheckBlocks(iteration_, guarded_, magnitudes);
  if (WaterDensifyDue(options_, iteration_, model_.num_dynamic()))
    out.densified = DensifyWaterNow();
  return out;
}

double JointTrainer::PairLossGradient(const Frame& frame, int partner,
                                      JointIterationStats* out) {
  const Frame& other = (*frames_)[partner];
  out->pair_frame = partner;
  pair_cost_->Reset(&other, other.time_index, LoopStructure::Of(model_));
  const int n = model_.gaussians.size();
  if (pair_grad_.size() != n ||
      pair_grad_.sh_degree != model_.gaussians.sh_degree)
    pair_grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  std::vector<double*> params = JointBlocks(&model_);
  std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
  std::vector<double*> pair_gradients = SplatRenderCost::Blocks(&pair_grad_);
  // Both backward passes add: the splats' rows are cleared here and
  // averaged below; the fields' buffers (zero already) are shared, take
  // the sum of both passes, flagged, and are halved below.
  const size_t splat_blocks = gradients.size();
  const std::vector<int32_t>& sizes = cost_->layout().sizes();
  for (size_t b = 0; b < splat_blocks; ++b) {
    std::fill(gradients[b], gradients[b] + sizes[b], 0.0);
    std::fill(pair_gradients[b], pair_gradients[b] + sizes[b], 0.0);
  }
  for (std::vector<double>& g : field_grad_) {
    gradients.push_back(g.data());
    pair_gradients.push_back(g.data());
  }
  const std::vector<char*> chunks = TriplaneChunkFlags();
  const double loss = cost_->RenderForGradient(params.data());
  out->photometric = cost_->last_photometric();
  out->mask = cost_->last_mask();
  out->residual = cost_->last_residual();
  const double pair_loss = pair_cost_->RenderForGradient(params.data());
  out->photometric = 0.5 * (out->photometric + pair_cost_->last_photometric());
  out->mask = 0.5 * (out->mask + pair_cost_->last_mask());
  out->residual = 0.5 * (out->residual + pair_cost_->last_residual());

  // The step follows 0.5 (loss + pair_loss + 2 energy): the energy's
  // gradient enters both backward passes at twice its weight and the sum
  // is halved below.
  const bool frame_first = frame.time_index < other.time_index;
  const JointRenderCost& first = frame_first ? *cost_ : *pair_cost_;
  const JointRenderCost& second = frame_first ? *pair_cost_ : *cost_;
  const Frame& a = frame_first ? frame : other;
  const Frame& b = frame_first ? other : frame;
  energy_grad_a_.assign(first.render().rgb.size(), 0.0);
  energy_grad_b_.assign(second.render().rgb.size(), 0.0);
  const double energy = energy_->Evaluate(
      first.render().rgb.data(), second.render().rgb.data(), a.image,
      b.image, energy_masks_ ? a.mask : cv::Mat(),
      energy_masks_ ? b.mask : cv::Mat(),
      2.0 * WaterLossRamp(options_, iteration_), energy_grad_a_.data(),
      energy_grad_b_.data(), &out->energy);
  const double texture = TextureLossGradient(
      first.render().rgb.data(), second.render().rgb.data(), a, b, out);
  cost_->BackwardWithImageGradient(
      params.data(),
      frame_first ? energy_grad_a_.data() : energy_grad_b_.data(),
      gradients.data(), /*accumulate=*/true, chunks.data());
  pair_cost_->BackwardWithImageGradient(
      params.data(),
      frame_first ? energy_grad_b_.data() : energy_grad_a_.data(),
      pair_gradients.data(), /*accumulate=*/true, chunks.data());
  for (size_t k = 0; k < splat_blocks; ++k)
    for (int i = 0; i < sizes[k]; ++i)
      gradients[k][i] = 0.5 * (gradients[k][i] + pair_gradients[k][i]);
  // The fields' sum: the triplanes' flagged chunks, the MLPs whole.
  for (size_t b = 0; b < field_grad_.size(); ++b) {
    std::vector<double>& g = field_grad_[b];
    const char* flags = chunks[splat_blocks + b];  // nullptr: an MLP
    for (size_t c = 0; c < static_cast<size_t>(NumGradientChunks(g.size()));
         ++c) {
      if (flags != nullptr && !flags[c]) continue;
      const size_t end = std::min(g.size(), (c + 1) * kGradientChunk);
      for (size_t i = c * kGradientChunk; i < end; ++i) g[i] *= 0.5;
    }
  }
  return 0.5 * (loss + pair_loss + energy + texture);
}

double JointTrainer::TextureLossGradient(const double* render_a,
                                         const double* render_b,
                                         const Frame& a, const Frame& b,
                                         JointIterationStats* out) {
  if (!texture_) return 0;
  // Each frame's distance at its full weight: the step halves the pair's
  // sum, so the term is the two frames' mean. The draws follow the
  // iteration, so a resumed run sees the same directions.
  const uint64_t draw = 2 * static_cast<uint64_t>(iteration_);
  const double ramp = WaterLossRamp(options_, iteration_);
  const double sum =
      texture_->Evaluate(render_a, a.image, energy_masks_ ? a.mask : cv::Mat(),
                         ramp, draw, energy_grad_a_.data()) +
      texture_->Evaluate(render_b, b.image, energy_masks_ ? b.mask : cv::Mat(),
                         ramp, draw + 1, energy_grad_b_.data());
  // The term itself, unramped (0 at iteration 0, where the ramp is).
  out->texture =
      ramp > 0 ? 0.5 * sum / (ramp * options_.water_texture.weight) : 0.0;
  return sum;
}

double JointTrainer::LoopTextureGradient(const Frame& frame,
                                         JointIterationStats* out) {
  loop_cost_->Reset(&frame, frame.time_index, LoopStructure::Of(model_));
  std::vector<double*> params = JointBlocks(&model_);
  loop_cost_->RenderForGradient(params.data());
  loop_grad_.assign(loop_cost_->render().rgb.size(), 0.0);
  const double ramp = WaterLossRamp(options_, iteration_);
  const double loss = loop_texture_->Evaluate(
      loop_cost_->render().rgb.data(), frame.image,
      energy_masks_ ? frame.mask : cv::Mat(), ramp,
      LoopTextureDraw(iteration_), loop_grad_.data());
  out->loop_texture =
      ramp > 0 ? loss / (ramp * options_.loop_texture_weight) : 0.0;
  std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
  for (std::vector<double>& g : field_grad_) gradients.push_back(g.data());
  const std::vector<char*> chunks = TriplaneChunkFlags();
  loop_cost_->BackwardWithImageGradient(params.data(), loop_grad_.data(),
                                        gradients.data(), /*accumulate=*/true,
                                        chunks.data());
  return loss;
}

WaterDensifyResult JointTrainer::DensifyWaterNow() {
  ScopedStage timer(Stage::kDensify);
  const int budget = WaterBudget(options_, initial_dynamic_);
  if (model_.num_dynamic() >= budget) return {};  // skip the ranking pass
  const int n = model_.gaussians.size();
  if (grad_.size() != n || grad_.sh_degree != model_.gaussians.sh_degree)
    grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  // grad_ and field_grad_ are scratch here: Step refills them.
  std::vector<double*> params = JointBlocks(&model_);
  std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
  for (std::vector<double>& g : field_grad_) gradients.push_back(g.data());
  DensityStats stats;
  stats.Reset(n);
  std::vector<int> radii;
  std::vector<double> mean2d_grads;
  for (int f : WaterDensifyViews(options_, train_, iteration_)) {
    const Frame& frame = (*frames_)[f];
    cost_->Reset(&frame, frame.time_index, LoopStructure::Of(model_));
    cost_->LossGradient(params.data(), gradients.data());
    rasterizer_.Radii(&radii);
    rasterizer_.Mean2dGradients(&mean2d_grads);
    stats.AddView(frame.camera.width, frame.camera.height, radii,
                  mean2d_grads);
  }
  // Step expects the field gradients zero.
  for (std::vector<double>& g : field_grad_) std::fill(g.begin(), g.end(), 0.0);
  std::vector<double> mean_grad;
  for (int i : model_.dynamic_index) mean_grad.push_back(stats.MeanGrad(i));
  const WaterDensifyResult result =
      DensifyRankedWater(options_, std::move(mean_grad), budget, iteration_,
                         *frames_, train_, &model_, &adam_);
  if (result.split + result.cloned > 0) UpdateScaleBounds();
  return result;
}

JointCheckpoint JointTrainer::Save() const {
  std::vector<std::vector<double>> m, v;
  for (const SparseAdam& adam : field_adam_) {
    m.push_back(adam.m());
    v.push_back(adam.v());
  }
  return PackJointCheckpoint(model_, iteration_, adam_.state(), std::move(m),
                             std::move(v), field_step_, sampler_.state(),
                             rng_);
}

void JointTrainer::Restore(const JointCheckpoint& c,
                           const std::string& source) {
  UnpackJointCheckpoint(c, source, &model_);
  iteration_ = c.iteration;
  ApplyMotionRamp(options_, iteration_, &model_);
  adam_.Restore(c.adam);
  UpdateScaleBounds();
  for (size_t b = 0; b < field_adam_.size(); ++b) {
    field_adam_[b].Restore(c.field_m[b], c.field_v[b]);
    std::fill(field_grad_[b].begin(), field_grad_[b].end(), 0.0);
  }
  field_step_ = c.field_step;
  RestoreSamplerAndRng(c, source, &sampler_, &rng_);
  grad_ = GaussianSet();
}

LoopModel JointTrainer::FinalModel(int* pruned) const {
  return FinalLoopModel(model_, *frames_, pruned);
}

std::unique_ptr<JointStageTrainer> MakeJointTrainer(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion) {
  return std::make_unique<JointTrainer>(frames, std::move(train), options,
                                        std::move(initial),
                                        std::move(motion));
}

}  // namespace es
