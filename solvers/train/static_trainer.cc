#include "solvers/train/static_trainer.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>

#include "core/base/input_error.h"
#include "core/base/stage_profile.h"
#include "costs/scalar_loss.h"
#include "core/base/rng_state.h"

namespace es {

ImageLossTerms StaticLossTerms(const StaticTrainerOptions& o, bool use_masks) {
  ImageLossTerms t;
  t.photometric_weight = 1.0;
  t.ssim_weight = o.ssim_weight;
  t.mask_weight = use_masks ? o.mask_weight : 0.0;
  return t;
}

RenderOptions StaticRenderOptions(const StaticTrainerOptions& o) {
  RenderOptions r;
  r.background = o.background;
  return r;
}

bool ShDegreeRises(const StaticTrainerOptions& o, int64_t iteration,
                   int sh_degree) {
  return iteration > 0 && o.sh_degree_interval > 0 &&
         iteration % o.sh_degree_interval == 0 &&
         sh_degree < o.max_sh_degree;
}

bool Densifying(const StaticTrainerOptions& o, int64_t iteration) {
  // As 3DGS (15k of 30k), the second half of a run only refines: a model
  // evaluated right after a clone / split step is measurably worse.
  return o.densify &&
         iteration < std::min<int64_t>(o.densify_options.until_iteration,
                                       o.iterations / 2);
}

bool DensifyDue(const StaticTrainerOptions& o, int64_t done) {
  const DensifyOptions& d = o.densify_options;
  return done > d.from_iteration && done % d.interval == 0;
}

bool OpacityResetDue(const StaticTrainerOptions& o, int64_t done) {
  // Only while densifying, so at least half the run re-learns opacities.
  const int interval = o.densify_options.opacity_reset_interval;
  return interval > 0 && done % interval == 0;
}

StaticTrainer::StaticTrainer(const std::vector<Frame>* frames,
                             std::vector<int> train,
                             const StaticTrainerOptions& options,
                             GaussianSet initial)
    : StageTrainerBase("Stage 1 training", frames, std::move(train), options),
      g_(std::move(initial)),
      sampler_(train_, options.seed),
      rng_(options.seed + 1),
      cost_(&(*frames)[train_.at(0)], 0, 0,
            StaticLossTerms(options, use_masks_),
            StaticRenderOptions(options), &rasterizer_) {
  comm_ = options_.comm != nullptr ? options_.comm : &SingleProcess();
  CheckBatchFrames(options_.batch_frames, *comm_);
  g_.CheckConsistent();
  CHECK_LE(g_.sh_degree, options_.max_sh_degree);
  guarded_ = GuardedSplatBlocks(g_, extent_, options_.splat_lr,
                                options_.lr_flags);
  adam_.Reset(g_);
  stats_.Reset(g_.size());
}

RenderOptions StaticTrainer::render_options() const {
  return StaticRenderOptions(options_);
}

IterationStats StaticTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (ShDegreeRises(options_, iteration_, g_.sh_degree)) {
    g_.SetShDegree(g_.sh_degree + 1);
    adam_.SetShDegree(g_.sh_degree);
  }
  IterationStats out;
  const int n = g_.size();
  if (grad_.size() != n || grad_.sh_degree != g_.sh_degree)
    grad_ = ZeroGaussians(n, g_.sh_degree);
  const bool densifying = Densifying(options_, iteration_);
  const bool batch = options_.batch_frames > 1;
  if (batch) {
    BatchGradient(densifying, &out);
  } else {
    out.frame = sampler_.Next();
    cost_.Reset(&(*frames_)[out.frame], n, g_.sh_degree);
    std::vector<double*> params = SplatRenderCost::Blocks(&g_);
    std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
    out.loss =
        EvaluateScalarLossGradient(cost_, params.data(), gradients.data());
    out.photometric = cost_.last_photometric();
    out.mask = cost_.last_mask();
  }
  const bool finite = std::isfinite(out.loss) && AllFinite(grad_);
  if (!guard_.Accept(iteration_ + 1, finite)) {
    out.skipped = true;
    ++iteration_;
    return out;
  }

  if (densifying && batch) {
    stats_.Add(batch_stats_);
  } else if (densifying) {
    ScopedStage stats_timer(Stage::kDensifyStats);
    // The cost's Backward ran on rasterizer_ with d loss / d image, so these
    // are this view's exact screen-space statistics.
    const Frame& frame = (*frames_)[out.frame];
    rasterizer_.Radii(&radii_);
    rasterizer_.Mean2dGradients(&mean2d_grads_);
    stats_.AddView(frame.camera.width, frame.camera.height, radii_,
                   mean2d_grads_);
  }
  adam_.Step(ScheduledSplatRates(options_.splat_lr, extent_, iteration_,
                                 options_.iterations, use_masks_),
             grad_, &g_);
  ++iteration_;
  guard_.CheckBlocks(iteration_, guarded_, SplatMagnitudes(g_));

  const DensifyOptions& d = options_.densify_options;
  if (densifying && DensifyDue(options_, iteration_)) {
    DensifyAndPrune(d, extent_, iteration_ > d.opacity_reset_interval, &rng_,
                    &g_, &adam_, &stats_);
  }
  if (densifying && OpacityResetDue(options_, iteration_))
    ResetOpacity(kStaticResetOpacity, &g_, &adam_);
  return out;
}

void StaticTrainer::BatchGradient(bool densifying, IterationStats* out) {
  const std::vector<int> batch = DrawBatch(&sampler_, options_.batch_frames);
  out->frame = batch[0];
  const int n = g_.size();
  std::vector<double*> params = SplatRenderCost::Blocks(&g_);
  std::vector<double*> gradients = SplatRenderCost::Blocks(&grad_);
  // Segments: the six splat blocks, the views' gradient sums and counts
  // (when densifying), the loss terms.
  std::vector<size_t> sizes = {grad_.means.size(),
                               grad_.log_scales.size(),
                               grad_.quats.size(),
                               grad_.opacity_logits.size(),
                               grad_.sh.size(),
                               grad_.dynamic_logits.size()};
  const int stats_segment = static_cast<int>(sizes.size());
  const size_t stats_size = densifying ? n : 0;
  sizes.insert(sizes.end(), {stats_size, stats_size, 3});
  const int terms_segment = stats_segment + 2;
  batch_sum_.Reset(sizes);
  if (densifying) batch_stats_.Reset(n);
  for (int k = 0; k < options_.batch_frames; ++k) {
    if (!RendersBatchFrame(*comm_, k)) continue;
    const Frame& frame = (*frames_)[batch[k]];
    cost_.Reset(&frame, n, g_.sh_degree);
    const double terms[3] = {
        EvaluateScalarLossGradient(cost_, params.data(), gradients.data()),
        cost_.last_photometric(), cost_.last_mask()};
    for (int b = 0; b < stats_segment; ++b) batch_sum_.Add(b, gradients[b]);
    batch_sum_.Add(terms_segment, terms);
    if (densifying) {
      ScopedStage stats_timer(Stage::kDensifyStats);
      rasterizer_.Radii(&radii_);
      rasterizer_.Mean2dGradients(&mean2d_grads_);
      batch_stats_.AddView(frame.camera.width, frame.camera.height, radii_,
                           mean2d_grads_);
    }
  }
  if (densifying) {
    batch_sum_.Add(stats_segment, batch_stats_.grad_sum.data());
    batch_sum_.Add(stats_segment + 1, batch_stats_.count.data());
  }
  batch_sum_.AllreduceSum(comm_);
  if (densifying) {
    ScopedStage reduce_timer(Stage::kAllreduce);
    comm_->AllreduceMax(batch_stats_.max_radius.data(), n);
  }
  for (int b = 0; b < stats_segment; ++b) {
    batch_sum_.Divide(b, options_.batch_frames);
    std::copy_n(batch_sum_.at(b), batch_sum_.size(b), gradients[b]);
  }
  batch_sum_.Divide(terms_segment, options_.batch_frames);
  out->loss = batch_sum_.at(terms_segment)[0];
  out->photometric = batch_sum_.at(terms_segment)[1];
  out->mask = batch_sum_.at(terms_segment)[2];
  if (densifying) {
    std::copy_n(batch_sum_.at(stats_segment), n, batch_stats_.grad_sum.data());
    std::copy_n(batch_sum_.at(stats_segment + 1), n, batch_stats_.count.data());
  }
}

Checkpoint StaticTrainer::Save() const {
  Checkpoint c;
  c.iteration = iteration_;
  c.gaussians = g_;
  c.adam = adam_.state();
  c.sampler = sampler_.state();
  c.rng = RngState(rng_);
  c.grad_sum = stats_.grad_sum;
  c.grad_count = stats_.count;
  c.max_radius = stats_.max_radius;
  c.batch_frames = options_.batch_frames;
  return c;
}

void StaticTrainer::Restore(const Checkpoint& c) {
  iteration_ = c.iteration;
  g_ = c.gaussians;
  adam_.Restore(c.adam);
  sampler_.Restore(c.sampler);
  if (!RestoreRngState(c.rng, &rng_))
    throw InputError("checkpoint: bad densification RNG state");
  stats_.grad_sum = c.grad_sum;
  stats_.count = c.grad_count;
  stats_.max_radius = c.max_radius;
  grad_ = GaussianSet();
}

}  // namespace es
