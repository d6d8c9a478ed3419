#include "solvers/train/joint_trainer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glog/logging.h>

#include "core/fields/gradient_chunks.h"
#include "core/io/input_error.h"
#include "core/loop/cycle_time.h"
#include "core/loop/frame_composer.h"
#include "core/profile/stage_profile.h"
#include "costs/splat_render_cost.h"
#include "solvers/checkpoint/rng_state.h"
#include "solvers/optim/lr_schedule.h"
#include "solvers/train/densify.h"
#include "solvers/train/water_particles.h"

namespace es {
namespace {

JointRenderTerms Terms(const JointTrainerOptions& o, bool use_masks) {
  JointRenderTerms t;
  t.photometric_weight = 1.0;
  t.ssim_weight = o.ssim_weight;
  t.mask_weight = use_masks ? o.mask_weight : 0.0;
  t.residual_weight = o.residual_weight;
  return t;
}

RenderOptions MakeRenderOptions(const JointTrainerOptions& o) {
  RenderOptions r;
  r.background = o.background;
  return r;
}

// For every training frame (by frame index), the training frame next to
// it in the video: the next one, else the previous one; -1 for none.
std::vector<int> TrainingNeighbours(const std::vector<Frame>& frames,
                                    const std::vector<int>& train) {
  std::vector<int> by_time;
  for (int f : train) {
    const int t = frames[f].time_index;
    if (t >= static_cast<int>(by_time.size())) by_time.resize(t + 1, -1);
    by_time[t] = f;
  }
  auto at = [&by_time](int t) {
    return t >= 0 && t < static_cast<int>(by_time.size()) ? by_time[t] : -1;
  };
  std::vector<int> partner(frames.size(), -1);
  for (int f : train) {
    const int t = frames[f].time_index;
    partner[f] = at(t + 1) >= 0 ? at(t + 1) : at(t - 1);
  }
  return partner;
}

void AppendBox(const Triplane& t, std::vector<double>* boxes) {
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_min()[i]);
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_max()[i]);
}

}  // namespace

int CyclesCovering(int frames, int cycle_length) {
  CHECK_GT(cycle_length, 0);
  // p = floor((i - t0) / L) for 0 <= i < frames and 0 <= t0 < L lies in
  // [-1, (frames - 1) / L]; the encoding is unambiguous for |p| < max.
  return std::max(1, frames - 1) / cycle_length + 2;
}

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
  CHECK_GT(options_.cycle_length, 0);
  CHECK_GT(options_.refresh_interval, 0);
  initial.CheckConsistent();
  model_.gaussians = std::move(initial);
  model_.cycle_length = options_.cycle_length;
  RefreshDynamicSet();
  initial_dynamic_ = model_.num_dynamic();
  Eigen::Vector3d lo, hi;
  FieldBox(model_.gaussians, model_.dynamic_index, &lo, &hi);
  if (options_.use_motion) {
    if (motion) {
      model_.motion.emplace(std::move(*motion));
      lo = model_.motion->triplane().box_min();
      hi = model_.motion->triplane().box_max();
    } else {
      model_.motion.emplace(options_.motion);
      model_.motion->SetBox(lo, hi);
    }
  }
  if (options_.use_residual) {
    ResidualFieldOptions r = options_.residual;
    r.cycle_length = options_.cycle_length;
    r.max_cycles = CyclesCovering(static_cast<int>(frames_->size()),
                                  options_.cycle_length);
    model_.residual.emplace(r);
    model_.residual->SetBox(lo, hi);
  }
  adam_.Reset(model_.gaussians);
  for (std::vector<double>* block : FieldBlocks()) {
    field_adam_.emplace_back(static_cast<int>(block->size()));
    field_grad_.emplace_back(block->size(), 0.0);
  }
  cost_.emplace(&(*frames_)[train_.at(0)],
                (*frames_)[train_.at(0)].time_index,
                LoopStructure::Of(model_), Terms(options_, use_masks_),
                render_options(), &rasterizer_);
  if (energy_on()) {
    partner_ = TrainingNeighbours(*frames_, train_);
    energy_masks_ = AllHaveMasks(*frames_, train_);
    energy_.emplace(options_.water_energy);
    // Its own rasterizer: both renders are kept until both backward passes.
    pair_cost_.emplace(&(*frames_)[train_.at(0)],
                       (*frames_)[train_.at(0)].time_index,
                       LoopStructure::Of(model_), Terms(options_, use_masks_),
                       render_options());
  }
}

void JointTrainer::SetSceneFlowPrior(std::vector<SceneFlowSample> samples) {
  CHECK(model_.motion) << "a scene-flow prior needs the motion field";
  flow_prior_.emplace(&*model_.motion, std::move(samples),
                      options_.flow_prior);
}

RenderOptions JointTrainer::render_options() const {
  return MakeRenderOptions(options_);
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

std::vector<std::vector<double>*> JointTrainer::FieldBlocks() {
  std::vector<std::vector<double>*> blocks;
  if (model_.motion) {
    blocks.push_back(&model_.motion->triplane_params());
    blocks.push_back(&model_.motion->mlp_params());
  }
  if (model_.residual) {
    blocks.push_back(&model_.residual->triplane_params());
    blocks.push_back(&model_.residual->mlp_params());
  }
  return blocks;
}

void JointTrainer::RefreshDynamicSet() {
  const std::vector<int> next =
      DynamicSet(model_.gaussians, options_.dynamic_threshold);
  std::vector<int> times(next.size());
  size_t old = 0;
  for (size_t k = 0; k < next.size(); ++k) {
    while (old < model_.dynamic_index.size() &&
           model_.dynamic_index[old] < next[k])
      ++old;
    if (old < model_.dynamic_index.size() &&
        model_.dynamic_index[old] == next[k]) {
      times[k] = model_.start_times[old];
    } else {
      times[k] = options_.random_start
                     ? DrawStartTime(options_.cycle_length, &rng_)
                     : 0;
    }
  }
  model_.dynamic_index = next;
  model_.start_times = std::move(times);
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

std::vector<double> JointTrainer::FieldLearningRates() const {
  auto decayed = [this](double initial) {
    return LogLinearLr(initial, initial * options_.field_lr_final_factor,
                       iteration_, options_.iterations);
  };
  std::vector<double> lr;
  if (model_.motion) {
    lr.push_back(decayed(options_.lr_motion_triplane));
    lr.push_back(decayed(options_.lr_motion_mlp));
  }
  if (model_.residual) {
    lr.push_back(decayed(options_.lr_residual_triplane));
    lr.push_back(decayed(options_.lr_residual_mlp));
  }
  return lr;
}

JointIterationStats JointTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (iteration_ > 0 && iteration_ % options_.refresh_interval == 0)
    RefreshDynamicSet();
  JointIterationStats out;
  out.frame = sampler_.Next();
  out.num_dynamic = model_.num_dynamic();
  const int n = model_.gaussians.size();
  if (grad_.size() != n || grad_.sh_degree != model_.gaussians.sh_degree)
    grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  const Frame& frame = (*frames_)[out.frame];
  cost_->Reset(&frame, frame.time_index, LoopStructure::Of(model_));
  const int partner = energy_on() ? partner_[out.frame] : -1;
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
    return out;
  }

  adam_.Step(ScheduledSplatRates(options_.splat_lr, extent_, iteration_,
                                 options_.iterations, use_masks_),
             grad_, &model_.gaussians);
  ClampDynamicScales();
  ++field_step_;
  const std::vector<double> lr = FieldLearningRates();
  std::vector<std::vector<double>*> blocks = FieldBlocks();
  bool params_finite = AllFinite(model_.gaussians);
  for (size_t b = 0; b < blocks.size(); ++b) {
    params_finite = field_adam_[b].Step(field_step_, lr[b],
                                        field_grad_[b].data(),
                                        blocks[b]->data()) &&
                    params_finite;
  }
  if (!fields_checked_) {
    for (const std::vector<double>* block : blocks)
      params_finite = params_finite && AllFinite(*block);
    fields_checked_ = true;
  }
  ++iteration_;
  guard_.CheckParameters(iteration_, params_finite);
  const WaterDensifyOptions& d = options_.water_densify;
  if (d.interval > 0 && iteration_ % d.interval == 0 &&
      iteration_ <= options_.iterations / 2 && model_.num_dynamic() > 0)
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
      energy_masks_ ? b.mask : cv::Mat(), 2.0, energy_grad_a_.data(),
      energy_grad_b_.data(), &out->energy);
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
  return 0.5 * (loss + pair_loss + energy);
}

WaterDensifyResult JointTrainer::DensifyWaterNow() {
  ScopedStage timer(Stage::kDensify);
  const WaterDensifyOptions& d = options_.water_densify;
  const int budget = static_cast<int>(d.max_growth * initial_dynamic_);
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
  const int views = std::min<int>(d.views, train_.size());
  const int offset = static_cast<int>(iteration_ / d.interval);
  for (int k = 0; k < views; ++k) {
    const int t = (static_cast<int>(k * train_.size() / views) + offset) %
                  static_cast<int>(train_.size());
    const Frame& frame = (*frames_)[train_[t]];
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
  for (int i : model_.dynamic_index) {
    const double g = stats.MeanGrad(i);
    mean_grad.push_back(std::isfinite(g) ? g : 0.0);
  }
  const std::vector<int> picked =
      PickWaterToDensify(model_.dynamic_index, mean_grad, d.fraction, budget);
  if (picked.empty()) return {};
  const std::vector<double> split_scale = PixelSizeInWorld(
      model_.gaussians, picked, *frames_, train_, d.split_pixels);
  std::seed_seq seq{static_cast<uint32_t>(options_.seed),
                    static_cast<uint32_t>(options_.seed >> 32),
                    static_cast<uint32_t>(iteration_),
                    static_cast<uint32_t>(iteration_ >> 32), 0x57u};
  std::mt19937_64 rng(seq);
  const WaterDensifyResult result =
      DensifyWater(picked, split_scale, &rng, &model_.gaussians, &adam_,
                   &model_.dynamic_index, &model_.start_times);
  UpdateScaleBounds();
  return result;
}

JointCheckpoint JointTrainer::Save() const {
  JointCheckpoint c;
  c.iteration = iteration_;
  c.gaussians = model_.gaussians;
  c.adam = adam_.state();
  c.dynamic_index = model_.dynamic_index;
  c.start_times = model_.start_times;
  auto append = [&c](const FieldParams& p, const Triplane& t, const Mlp& m) {
    c.field_params.emplace_back(p.triplane, p.triplane + t.num_params());
    c.field_params.emplace_back(p.mlp, p.mlp + m.num_params());
  };
  if (model_.motion) {
    append(model_.motion->params(), model_.motion->triplane(),
           model_.motion->mlp());
  }
  if (model_.residual) {
    append(model_.residual->params(), model_.residual->triplane(),
           model_.residual->mlp());
  }
  for (const SparseAdam& adam : field_adam_) {
    c.field_m.push_back(adam.m());
    c.field_v.push_back(adam.v());
  }
  if (model_.motion) AppendBox(model_.motion->triplane(), &c.field_boxes);
  if (model_.residual) AppendBox(model_.residual->triplane(), &c.field_boxes);
  c.field_step = field_step_;
  c.sampler = sampler_.state();
  c.rng = RngState(rng_);
  return c;
}

void JointTrainer::Restore(const JointCheckpoint& c,
                           const std::string& source) {
  std::vector<std::vector<double>*> blocks = FieldBlocks();
  bool match = c.field_params.size() == blocks.size() &&
               c.gaussians.sh_degree == model_.gaussians.sh_degree;
  match = match && c.field_m.size() == blocks.size() &&
          c.field_v.size() == blocks.size();
  for (size_t b = 0; match && b < blocks.size(); ++b) {
    match = c.field_params[b].size() == blocks[b]->size() &&
            c.field_m[b].size() == blocks[b]->size() &&
            c.field_v[b].size() == blocks[b]->size();
  }
  if (!match)
    throw InputError(source +
                     ": checkpoint fields or SH degree do not match the "
                     "options of this run");
  iteration_ = c.iteration;
  model_.gaussians = c.gaussians;
  adam_.Restore(c.adam);
  model_.dynamic_index = c.dynamic_index;
  model_.start_times = c.start_times;
  UpdateScaleBounds();
  for (size_t b = 0; b < blocks.size(); ++b) *blocks[b] = c.field_params[b];
  for (size_t b = 0; b < blocks.size(); ++b) {
    field_adam_[b].Restore(c.field_m[b], c.field_v[b]);
    std::fill(field_grad_[b].begin(), field_grad_[b].end(), 0.0);
  }
  fields_checked_ = false;
  auto box = [&c](int field, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
    *lo = Eigen::Vector3d(&c.field_boxes[6 * field]);
    *hi = Eigen::Vector3d(&c.field_boxes[6 * field + 3]);
  };
  Eigen::Vector3d lo, hi;
  int field = 0;
  if (model_.motion) {
    box(field++, &lo, &hi);
    model_.motion->SetBox(lo, hi);
  }
  if (model_.residual) {
    box(field++, &lo, &hi);
    model_.residual->SetBox(lo, hi);
  }
  field_step_ = c.field_step;
  try {
    sampler_.Restore(c.sampler);
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  if (!RestoreRngState(c.rng, &rng_))
    throw InputError(source + ": bad RNG state in checkpoint");
  grad_ = GaussianSet();
}

LoopModel JointTrainer::FinalModel(int* pruned) const {
  LoopModel model = model_;
  // Every frame of the video, registered by COLMAP or not.
  int video_frames = 0;
  for (const Frame& f : *frames_)
    video_frames = std::max(video_frames, f.time_index + 1);
  const int removed = PruneInvisible(video_frames, &model);
  if (pruned) *pruned = removed;
  return model;
}

int PruneInvisible(int num_frames, LoopModel* model) {
  GaussianSet& g = model->gaussians;
  std::vector<double> peak(g.opacity_logits);  // largest logit shown
  if (model->num_dynamic() > 0 && model->residual) {
    const LoopModelView view = LoopModelView::Of(*model);
    FrameComposer composer;
    const int frames = std::max(num_frames, 2 * model->cycle_length);
    for (int i = 0; i < frames; ++i) {
      const SplatView& splats = composer.Compose(view, i);
      for (int g_index : model->dynamic_index)
        peak[g_index] =
            std::max(peak[g_index], splats.opacity_logits[g_index]);
    }
  }
  const double threshold = Logit(kInvisibleOpacity);
  std::vector<bool> keep(g.size());
  std::vector<int> new_index(g.size(), -1);
  int kept = 0;
  for (int i = 0; i < g.size(); ++i) {
    keep[i] = peak[i] >= threshold;
    if (keep[i]) new_index[i] = kept++;
  }
  const int removed = g.size() - kept;
  if (removed == 0) return 0;
  g.Filter(keep);
  std::vector<int> dynamic_index, start_times;
  for (int k = 0; k < model->num_dynamic(); ++k) {
    const int i = model->dynamic_index[k];
    if (!keep[i]) continue;
    dynamic_index.push_back(new_index[i]);
    start_times.push_back(model->start_times[k]);
  }
  model->dynamic_index = std::move(dynamic_index);
  model->start_times = std::move(start_times);
  return removed;
}

}  // namespace es
