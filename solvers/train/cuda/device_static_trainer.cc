#include "solvers/train/cuda/device_static_trainer.h"

#include <glog/logging.h>

#include <cmath>
#include <string>
#include <utility>

#include "core/base/input_error.h"
#include "core/base/stage_profile.h"
#include "core/base/rng_state.h"
#include "solvers/train/splat_training.h"

namespace es {
namespace cuda {
DeviceStaticTrainer::DeviceStaticTrainer(const std::vector<Frame>* frames,
                                         std::vector<int> train,
                                         const StaticTrainerOptions& options,
                                         GaussianSet initial)
    : StageTrainerBase("Stage 1 training", frames, std::move(train), options),
      images_(*frames, train_, use_masks_),
      sampler_(train_, options.seed),
      rng_(options.seed + 1),
      cost_(StaticLossTerms(options, use_masks_), options.background,
            &rasterizer_) {
  initial.CheckConsistent();
  CHECK_LE(initial.sh_degree, options_.max_sh_degree);
  guarded_ = GuardedSplatBlocks(initial, extent_, options_.splat_lr,
                                options_.lr_flags);
  HostState start;
  start.g = std::move(initial);
  start.adam.Reset(start.g);
  start.stats.Reset(start.g.size());
  Upload(start);
}

RenderOptions DeviceStaticTrainer::render_options() const {
  return StaticRenderOptions(options_);
}

IterationStats DeviceStaticTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (ShDegreeRises(options_, iteration_, g_.sh_degree())) {
    HostState s = Download();
    s.g.SetShDegree(s.g.sh_degree + 1);
    s.adam.SetShDegree(s.g.sh_degree);
    Upload(s);
  }
  IterationStats out;
  out.frame = sampler_.Next();
  const Frame& frame = (*frames_)[out.frame];
  const int n = g_.size();
  if (grad_.size() != n || grad_.sh_degree() != g_.sh_degree())
    grad_.ResizeZero(n, g_.sh_degree());
  cost_.Reset(frame.camera, images_.image(out.frame),
              images_.mask(out.frame), n, g_.sh_degree());
  std::vector<double*> params = g_.BlockPointers();
  std::vector<double*> gradients = grad_.BlockPointers();
  out.loss = EvaluateDeviceScalarLossGradient(cost_, params.data(),
                                              gradients.data());
  out.photometric = cost_.last_photometric();
  out.mask = cost_.last_mask();
  const bool finite = std::isfinite(out.loss) && grad_.AllFinite();
  if (!guard_.Accept(iteration_ + 1, finite)) {
    out.skipped = true;
    ++iteration_;
    return out;
  }

  const bool densifying = Densifying(options_, iteration_);
  if (densifying) {
    ScopedStage stats_timer(Stage::kDensifyStats);
    // The cost's backward ran on rasterizer_: this view's statistics.
    stats_.AddView(frame.camera.width, frame.camera.height, rasterizer_);
  }
  adam_.Step(ScheduledSplatRates(options_.splat_lr, extent_, iteration_,
                                 options_.iterations, use_masks_),
             grad_.Blocks(), g_.Blocks());
  host_g_current_ = false;
  ++iteration_;
  guard_.CheckBlocks(iteration_, guarded_, g_.MaxMagnitudes());

  const bool densify = densifying && DensifyDue(options_, iteration_);
  const bool reset = densifying && OpacityResetDue(options_, iteration_);
  if (densify || reset) {
    HostState s = Download();
    const DensifyOptions& d = options_.densify_options;
    if (densify)
      DensifyAndPrune(d, extent_, iteration_ > d.opacity_reset_interval, &rng_,
                      &s.g, &s.adam, &s.stats);
    if (reset) ResetOpacity(kStaticResetOpacity, &s.g, &s.adam);
    Upload(s);
  }
  return out;
}

const GaussianSet& DeviceStaticTrainer::gaussians() const {
  if (!host_g_current_) {
    g_.Download(&host_g_);
    host_g_current_ = true;
  }
  return host_g_;
}

DeviceStaticTrainer::HostState DeviceStaticTrainer::Download() const {
  HostState s;
  g_.Download(&s.g);
  s.adam.Restore(adam_.State());
  stats_.Download(&s.stats);
  return s;
}

void DeviceStaticTrainer::Upload(const HostState& s) {
  CHECK_EQ(s.stats.size(), s.g.size());
  g_.Upload(s.g);
  adam_.Restore(s.adam.state());
  stats_.Upload(s.stats);
  host_g_current_ = false;
}

Checkpoint DeviceStaticTrainer::Save() const {
  HostState s = Download();
  Checkpoint c;
  c.iteration = iteration_;
  c.gaussians = std::move(s.g);
  c.adam = s.adam.state();
  c.sampler = sampler_.state();
  c.rng = RngState(rng_);
  c.grad_sum = std::move(s.stats.grad_sum);
  c.grad_count = std::move(s.stats.count);
  c.max_radius = std::move(s.stats.max_radius);
  return c;
}

void DeviceStaticTrainer::Restore(const Checkpoint& c) {
  HostState s;
  s.g = c.gaussians;
  s.adam.Restore(c.adam);
  s.stats.grad_sum = c.grad_sum;
  s.stats.count = c.grad_count;
  s.stats.max_radius = c.max_radius;
  const size_t n = s.g.size();
  if (c.grad_sum.size() != n || c.grad_count.size() != n ||
      c.max_radius.size() != n)
    throw InputError("checkpoint: densification statistics for " +
                     std::to_string(c.grad_sum.size()) + " Gaussians, not " +
                     std::to_string(n));
  iteration_ = c.iteration;
  Upload(s);
  sampler_.Restore(c.sampler);
  if (!RestoreRngState(c.rng, &rng_))
    throw InputError("checkpoint: bad densification RNG state");
}

std::unique_ptr<StaticStageTrainer> MakeDeviceStaticTrainer(
    const Scene& scene, const StaticTrainerOptions& options) {
  return std::make_unique<DeviceStaticTrainer>(
      &scene.frames, scene.train, options, InitialStaticGaussians(scene));
}

}  // namespace cuda
}  // namespace es
