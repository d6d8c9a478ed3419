#include "solvers/train/joint_trainer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <glog/logging.h>

#include "core/io/input_error.h"
#include "core/loop/frame_composer.h"
#include "core/metrics/image_metrics.h"
#include "solvers/optim/lr_schedule.h"
#include "solvers/train/static_trainer.h"
#include "solvers/train/water_particles.h"

namespace es {
namespace {

// Fraction of the dynamic Gaussians' extent added around them, so the
// fields still see their neighbourhood as positions move.
constexpr double kBoxPadding = 0.1;
// Smallest box half-size, for a single (or no) dynamic Gaussian.
constexpr double kMinBoxMargin = 1e-3;

bool AllHaveMasks(const std::vector<Frame>& frames,
                  const std::vector<int>& indices) {
  for (int i : indices)
    if (frames[i].mask.empty()) return false;
  return true;
}

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

void AppendBox(const Triplane& t, std::vector<double>* boxes) {
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_min()[i]);
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_max()[i]);
}

// Mean of the finite values (NaN if none).
class Average {
 public:
  void Add(double v) {
    if (!std::isfinite(v)) return;
    sum_ += v;
    ++count_;
  }
  double Get() const {
    return count_ ? sum_ / count_ : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double sum_ = 0;
  int count_ = 0;
};

}  // namespace

int CyclesCovering(int frames, int cycle_length) {
  CHECK_GT(cycle_length, 0);
  // p = floor((i - t0) / L) for 0 <= i < frames and 0 <= t0 < L lies in
  // [-1, (frames - 1) / L]; the encoding is unambiguous for |p| < max.
  return std::max(1, frames - 1) / cycle_length + 2;
}

std::vector<int> DynamicSet(const GaussianSet& g, double threshold) {
  std::vector<int> out;
  for (int i = 0; i < g.size(); ++i)
    if (Sigmoid(g.dynamic_logits[i]) > threshold) out.push_back(i);
  return out;
}

void FieldBox(const GaussianSet& g, const std::vector<int>& indices,
              Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  lo->setConstant(std::numeric_limits<double>::infinity());
  hi->setConstant(-std::numeric_limits<double>::infinity());
  auto add = [&](int i) {
    const Eigen::Vector3d x(&g.means[3 * i]);
    if (!x.allFinite()) return;
    *lo = lo->cwiseMin(x);
    *hi = hi->cwiseMax(x);
  };
  if (indices.empty()) {
    for (int i = 0; i < g.size(); ++i) add(i);
  } else {
    for (int i : indices) add(i);
  }
  if (!lo->allFinite()) {
    lo->setConstant(-1.0);
    hi->setConstant(1.0);
    return;
  }
  const Eigen::Vector3d pad =
      (kBoxPadding * (*hi - *lo)).cwiseMax(kMinBoxMargin);
  *lo -= pad;
  *hi += pad;
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
    field_m_.emplace_back(block->size(), 0.0);
    field_v_.emplace_back(block->size(), 0.0);
    field_grad_.emplace_back(block->size(), 0.0);
  }
  cost_.emplace(&(*frames_)[train_.at(0)], train_.at(0),
                LoopStructure::Of(model_), Terms(options_, use_masks_),
                render_options(), &rasterizer_);
}

RenderOptions JointTrainer::render_options() const {
  return MakeRenderOptions(options_);
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
      // Our own reduction: distributions are not portable across standard
      // libraries, and a resumed run must replay identically.
      times[k] = options_.random_start
                     ? static_cast<int>(rng_() % options_.cycle_length)
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

GaussianLearningRates JointTrainer::LearningRates() const {
  GaussianLearningRates lr;
  lr.means = extent_ * LogLinearLr(options_.lr_means_initial,
                                   options_.lr_means_final, iteration_,
                                   options_.iterations);
  lr.log_scales = options_.lr_log_scales;
  lr.quats = options_.lr_quats;
  lr.opacity_logits = options_.lr_opacity;
  lr.sh_dc = options_.lr_sh_dc;
  lr.sh_rest = options_.lr_sh_rest;
  lr.dynamic_logits = use_masks_ ? options_.lr_dynamic : 0.0;
  return lr;
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
  if (iteration_ > 0 && iteration_ % options_.refresh_interval == 0)
    RefreshDynamicSet();
  JointIterationStats out;
  out.frame = sampler_.Next();
  out.num_dynamic = model_.num_dynamic();
  const int n = model_.gaussians.size();
  if (grad_.size() != n || grad_.sh_degree != model_.gaussians.sh_degree)
    grad_ = ZeroGaussians(n, model_.gaussians.sh_degree);
  cost_->Reset(&(*frames_)[out.frame], out.frame, LoopStructure::Of(model_));
  std::vector<double*> params = JointBlocks(&model_);
  std::vector<double*> jacobians = SplatRenderCost::Blocks(&grad_);
  for (std::vector<double>& g : field_grad_) jacobians.push_back(g.data());
  double r = 0;
  CHECK(cost_->Evaluate(params.data(), &r, jacobians.data()));
  // The Jacobian row of the one residual is dl/dtheta / r.
  const std::vector<int32_t>& sizes = cost_->parameter_block_sizes();
  for (size_t b = 0; b < jacobians.size(); ++b) {
    double* block = jacobians[b];
    const int size = sizes[b];
#pragma omp parallel for if (size > 65536) schedule(static)
    for (int i = 0; i < size; ++i) block[i] *= r;
  }
  out.loss = 0.5 * r * r;
  out.photometric = cost_->last_photometric();
  out.mask = cost_->last_mask();
  out.residual = cost_->last_residual();
  out.euler = cost_->last_euler_stats();
  bool finite = std::isfinite(r) && AllFinite(grad_);
  for (const std::vector<double>& g : field_grad_)
    finite = finite && AllFinite(g);
  if (!guard_.Accept(iteration_ + 1, finite)) {
    out.skipped = true;
    ++iteration_;
    return out;
  }

  adam_.Step(LearningRates(), grad_, &model_.gaussians);
  ClampDynamicScales();
  ++field_step_;
  const std::vector<double> lr = FieldLearningRates();
  std::vector<std::vector<double>*> blocks = FieldBlocks();
  const AdamOptions adam_options;
  for (size_t b = 0; b < blocks.size(); ++b) {
    AdamUpdate(adam_options, field_step_, lr[b],
               static_cast<int>(blocks[b]->size()), field_grad_[b].data(),
               field_m_[b].data(), field_v_[b].data(), blocks[b]->data());
  }
  ++iteration_;
  bool params_finite = AllFinite(model_.gaussians);
  for (const std::vector<double>* block : blocks)
    params_finite = params_finite && AllFinite(*block);
  guard_.CheckParameters(iteration_, params_finite);
  return out;
}

JointCheckpoint JointTrainer::Save() const {
  JointCheckpoint c;
  c.iteration = iteration_;
  c.gaussians = model_.gaussians;
  c.adam_m = adam_.m();
  c.adam_v = adam_.v();
  c.adam_step = adam_.step();
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
  c.field_m = field_m_;
  c.field_v = field_v_;
  if (model_.motion) AppendBox(model_.motion->triplane(), &c.field_boxes);
  if (model_.residual) AppendBox(model_.residual->triplane(), &c.field_boxes);
  c.field_step = field_step_;
  c.sampler = sampler_.state();
  std::ostringstream rng;
  rng << rng_;
  c.rng = rng.str();
  return c;
}

void JointTrainer::Restore(const JointCheckpoint& c,
                           const std::string& source) {
  std::vector<std::vector<double>*> blocks = FieldBlocks();
  bool match = c.field_params.size() == blocks.size() &&
               c.gaussians.sh_degree == model_.gaussians.sh_degree;
  for (size_t b = 0; match && b < blocks.size(); ++b)
    match = c.field_params[b].size() == blocks[b]->size();
  if (!match)
    throw InputError(source +
                     ": checkpoint fields or SH degree do not match the "
                     "options of this run");
  iteration_ = c.iteration;
  model_.gaussians = c.gaussians;
  adam_.m() = c.adam_m;
  adam_.v() = c.adam_v;
  adam_.set_step(c.adam_step);
  model_.dynamic_index = c.dynamic_index;
  model_.start_times = c.start_times;
  UpdateScaleBounds();
  for (size_t b = 0; b < blocks.size(); ++b) *blocks[b] = c.field_params[b];
  field_m_ = c.field_m;
  field_v_ = c.field_v;
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
  std::istringstream rng(c.rng);
  rng >> rng_;
  if (rng.fail()) throw InputError(source + ": bad RNG state in checkpoint");
  grad_ = GaussianSet();
}

LoopModel JointTrainer::FinalModel(int* pruned) const {
  LoopModel model = model_;
  const int removed =
      PruneInvisible(static_cast<int>(frames_->size()), &model);
  if (pruned) *pruned = removed;
  return model;
}

int PruneInvisible(int num_frames, LoopModel* model) {
  GaussianSet& g = model->gaussians;
  std::vector<double> peak(g.opacity_logits);  // largest logit shown
  if (model->num_dynamic() > 0 && model->residual) {
    const LoopSplatView view = LoopSplatView::Of(*model);
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

LoopMetrics EvaluateLoopModel(const LoopModel& model,
                              const std::vector<Frame>& frames,
                              const std::vector<int>& indices,
                              const RenderOptions& options) {
  const LoopSplatView view = LoopSplatView::Of(model);
  FrameComposer composer;
  Rasterizer rasterizer;
  RenderResult render;
  Average psnr, ssim, psnr_water, ssim_water;
  for (int index : indices) {
    const Frame& f = frames[index];
    rasterizer.Forward(f.camera, composer.Compose(view, index), options,
                       &render);
    const cv::Mat x(render.height, render.width, CV_64FC3,
                    render.rgb.data());
    cv::Mat y;
    f.image.convertTo(y, CV_64F);
    psnr.Add(Psnr(x, y));
    ssim.Add(Ssim(x, y));
    if (f.mask.empty()) continue;
    psnr_water.Add(MaskedPsnr(x, y, f.mask));
    ssim_water.Add(MaskedSsim(x, y, f.mask));
  }
  LoopMetrics out;
  out.frames = static_cast<int>(indices.size());
  out.psnr = psnr.Get();
  out.ssim = ssim.Get();
  out.psnr_water = psnr_water.Get();
  out.ssim_water = ssim_water.Get();
  return out;
}

}  // namespace es
