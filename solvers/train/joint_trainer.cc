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
#include "core/base/lr_schedule.h"
#include "solvers/train/densify.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/water_particles.h"

namespace es {
JointTrainer::JointTrainer(const std::vector<Frame>* frames,
                           std::vector<int> train,
                           const JointTrainerOptions& options,
                           GaussianSet initial,
                           std::optional<MotionField> motion)
    : StageTrainerBase("Stage 3 training", frames, std::move(train), options),
      sampler_(train_, options.seed),
      rng_(options.seed + 1) {
  comm_ = options_.comm != nullptr ? options_.comm : &SingleProcess();
  CheckBatchFrames(options_.batch_frames, *comm_);
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
  const bool water_masks =
      WaterLossOn(options_) && AllHaveMasks(*frames_, train_);
  objective_.emplace(&(*frames_)[train_.at(0)], LoopStructure::Of(model_),
                     JointObjectiveOptionsOf(options_, use_masks_,
                                             water_masks));
  if (PairLossOn(options_)) partner_ = TrainingNeighbours(*frames_, train_);
  ApplyMotionRamp(options_, iteration_, &model_);
}

void JointTrainer::SetSceneFlowPrior(std::vector<SceneFlowSample> samples) {
  CHECK(model_.motion) << "a scene-flow prior needs the motion field";
  objective_->SetSceneFlowPrior(*model_.motion, std::move(samples),
                                options_.flow_prior, options_.iterations,
                                options_.seed);
}

RenderOptions JointTrainer::render_options() const {
  return JointRenderOptions(options_);
}

std::vector<char*> JointTrainer::TriplaneChunkFlags() {
  const JointBlockLayout& layout = objective_->layout();
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

std::vector<double*> JointTrainer::GradientBlocks() {
  const int n = model_.gaussians.size();
  if (grad_.size() != n || grad_.sh_degree != model_.gaussians.sh_degree)
    grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
  for (std::vector<double>& g : field_grad_) gradients.push_back(g.data());
  return gradients;
}

JointIterationStats JointTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (DynamicSetRefreshDue(options_, iteration_)) RefreshDynamicSet();
  JointIterationStats out;
  out.num_dynamic = model_.num_dynamic();
  std::vector<double*> params = JointBlocks(&model_);
  std::vector<double*> gradients = GradientBlocks();
  const bool batch = options_.batch_frames > 1;
  if (batch) {
    out.loss = BatchGradient(params.data(), gradients.data(), &out);
  } else {
    out.frame = sampler_.Next();
    if (PairLossOn(options_)) out.pair_frame = partner_[out.frame];
    const Frame* partner =
        out.pair_frame >= 0 ? &(*frames_)[out.pair_frame] : nullptr;
    const std::vector<char*> chunks = TriplaneChunkFlags();
    out.loss = objective_->Evaluate(
        LoopStructure::Of(model_), params.data(), (*frames_)[out.frame],
        partner, WaterLossRamp(options_, iteration_), iteration_,
        gradients.data(), chunks.data(), &out);
  }
  // Every writer of the triplanes' gradients (the costs, the flow prior)
  // flagged the chunks it wrote into their SparseAdam's flags, so only
  // those are read; the MLPs' small blocks are scanned whole. A batch's
  // gradient came dense from the sum over the ranks.
  bool finite = std::isfinite(out.loss) && AllFinite(grad_);
  for (size_t b = 0; b < field_grad_.size(); ++b) {
    SparseAdam& adam = field_adam_[b];
    const bool flagged = b % 2 == 0 && !batch;
    finite = (flagged ? adam.ScanFlagged(field_grad_[b].data())
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

double JointTrainer::BatchGradient(double const* const* params,
                                  double** gradients,
                                  JointIterationStats* out) {
  const std::vector<int> batch = DrawBatch(&sampler_, options_.batch_frames);
  out->frame = batch[0];
  if (PairLossOn(options_)) out->pair_frame = partner_[out->frame];
  // Segments: the layout's blocks (the splats', then the fields'; sized
  // from the buffers: the objective's layout follows a densification only
  // at its next evaluation), then the loss and its terms.
  std::vector<size_t> sizes = {grad_.means.size(), grad_.log_scales.size(),
                               grad_.quats.size(), grad_.opacity_logits.size(),
                               grad_.sh.size(), grad_.dynamic_logits.size()};
  for (const std::vector<double>& g : field_grad_) sizes.push_back(g.size());
  const int num_blocks = static_cast<int>(sizes.size());
  constexpr int kTerms = 8;
  sizes.push_back(kTerms);
  batch_sum_.Reset(sizes);
  frame_field_grad_.resize(field_grad_.size());
  std::vector<double*> frame_gradients(gradients, gradients + num_blocks);
  for (size_t f = 0; f < field_grad_.size(); ++f) {
    frame_field_grad_[f].assign(field_grad_[f].size(), 0.0);
    frame_gradients[kNumSplatBlocks + f] = frame_field_grad_[f].data();
  }
  const LoopStructure structure = LoopStructure::Of(model_);
  const double ramp = WaterLossRamp(options_, iteration_);
  EulerStats euler;
  for (int k = 0; k < options_.batch_frames; ++k) {
    if (!RendersBatchFrame(*comm_, k)) continue;
    const int pair = PairLossOn(options_) ? partner_[batch[k]] : -1;
    JointObjectiveTerms t;
    const double loss = objective_->EvaluateFrame(
        structure, params, (*frames_)[batch[k]],
        pair >= 0 ? &(*frames_)[pair] : nullptr, ramp, iteration_,
        frame_gradients.data(), nullptr, &t);
    for (int b = 0; b < num_blocks; ++b) batch_sum_.Add(b, frame_gradients[b]);
    for (std::vector<double>& g : frame_field_grad_)
      std::fill(g.begin(), g.end(), 0.0);
    const double terms[kTerms] = {loss,          t.photometric,  t.mask,
                                  t.residual,    t.energy.motion,
                                  t.energy.detail, t.texture,
                                  t.loop_texture};
    batch_sum_.Add(num_blocks, terms);
    euler.velocity_evaluations += t.euler.velocity_evaluations;
    euler.nonfinite_velocities += t.euler.nonfinite_velocities;
    euler.clamped_steps += t.euler.clamped_steps;
  }
  batch_sum_.AllreduceSum(comm_);
  for (int b = 0; b <= num_blocks; ++b) {
    batch_sum_.Divide(b, options_.batch_frames);
    if (b < num_blocks)
      std::copy_n(batch_sum_.at(b), batch_sum_.size(b), gradients[b]);
  }
  const double* terms = batch_sum_.at(num_blocks);
  out->photometric = terms[1];
  out->mask = terms[2];
  out->residual = terms[3];
  out->energy.motion = terms[4];
  out->energy.detail = terms[5];
  out->texture = terms[6];
  out->loop_texture = terms[7];
  out->euler = euler;  // this rank's frames
  return terms[0] +
         objective_->AddSceneFlowPrior(params, iteration_, gradients, nullptr,
                                       out);
}

WaterDensifyResult JointTrainer::DensifyWaterNow() {
  ScopedPass pass(Pass::kDensify);  // its renders too
  ScopedStage timer(Stage::kDensify);
  const int budget = WaterBudget(options_, initial_dynamic_);
  if (model_.num_dynamic() >= budget) return {};  // skip the ranking pass
  const int n = model_.gaussians.size();
  // grad_ and field_grad_ are scratch here: Step refills them.
  std::vector<double*> params = JointBlocks(&model_);
  std::vector<double*> gradients = GradientBlocks();
  DensityStats stats;
  stats.Reset(n);
  std::vector<int> radii;
  std::vector<double> mean2d_grads;
  for (int f : WaterDensifyViews(options_, train_, iteration_)) {
    const Frame& frame = (*frames_)[f];
    objective_->FitGradient(LoopStructure::Of(model_), params.data(), frame,
                            gradients.data());
    objective_->rasterizer().Radii(&radii);
    objective_->rasterizer().Mean2dGradients(&mean2d_grads);
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
  JointCheckpoint c = PackJointCheckpoint(
      model_, iteration_, adam_.state(), std::move(m), std::move(v),
      field_step_, sampler_.state(), rng_);
  c.batch_frames = options_.batch_frames;
  return c;
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
  if (objective_->has_scene_flow_prior())
    objective_->UpdateSceneFlowPriorField(*model_.motion);
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
