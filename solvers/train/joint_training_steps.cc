#include "solvers/train/joint_training_steps.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/loop/cycle_time.h"
#include "core/model/dynamic_set.h"
#include "core/base/rng_state.h"
#include "core/base/lr_schedule.h"
#include "core/loop/frame_composer.h"
#include "solvers/train/water_particles.h"

namespace es {
namespace {

void AppendBox(const Triplane& t, std::vector<double>* boxes) {
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_min()[i]);
  for (int i = 0; i < 3; ++i) boxes->push_back(t.box_max()[i]);
}

// 0 at iteration 0, rising linearly to 1 at `fraction` of the iterations.
double Ramp(double fraction, int iterations, int64_t iteration) {
  const double ramp_iterations = fraction * iterations;
  if (!(ramp_iterations > 0)) return 1.0;
  return std::min(1.0, static_cast<double>(iteration) / ramp_iterations);
}

}  // namespace

int CyclesCovering(int frames, int cycle_length) {
  CHECK_GT(cycle_length, 0);
  // p = floor((i - t0) / L) for 0 <= i < frames and 0 <= t0 < L lies in
  // [-1, (frames - 1) / L]; the encoding is unambiguous for |p| < max.
  return std::max(1, frames - 1) / cycle_length + 2;
}

JointRenderTerms JointLossTerms(const JointTrainerOptions& o, bool use_masks) {
  JointRenderTerms t;
  t.photometric_weight = 1.0;
  t.ssim_weight = o.ssim_weight;
  t.mask_weight = use_masks ? o.mask_weight : 0.0;
  t.residual_weight = o.residual_weight;
  return t;
}

RenderOptions JointRenderOptions(const JointTrainerOptions& o) {
  RenderOptions r;
  r.background = o.background;
  return r;
}

JointObjectiveOptions JointObjectiveOptionsOf(const JointTrainerOptions& o,
                                              bool use_masks,
                                              bool water_masks) {
  JointObjectiveOptions j;
  j.terms = JointLossTerms(o, use_masks);
  j.render = JointRenderOptions(o);
  j.euler = o.euler;
  j.water_energy = o.water_energy;
  j.water_texture = o.water_texture;
  j.loop_texture_weight = o.loop_texture_weight;
  j.loop_texture_interval = o.loop_texture_interval;
  j.water_masks = water_masks;
  return j;
}

bool WaterEnergyOn(const JointTrainerOptions& o) {
  return JointObjectiveOptionsOf(o, false, false).energy_on();
}

bool WaterTextureOn(const JointTrainerOptions& o) {
  return JointObjectiveOptionsOf(o, false, false).texture_on();
}

bool PairLossOn(const JointTrainerOptions& o) {
  return JointObjectiveOptionsOf(o, false, false).pair_on();
}

bool WaterLossOn(const JointTrainerOptions& o) {
  const JointObjectiveOptions j = JointObjectiveOptionsOf(o, false, false);
  return j.pair_on() || j.loop_texture_on();
}

bool LoopTextureDue(const JointTrainerOptions& o, int64_t iteration) {
  return JointObjectiveOptionsOf(o, false, false).loop_texture_due(iteration);
}

double WaterLossRamp(const JointTrainerOptions& o, int64_t iteration) {
  return Ramp(o.water_loss_warmup, o.iterations, iteration);
}

double MotionRamp(const JointTrainerOptions& o, int64_t iteration) {
  return Ramp(o.motion_warmup, o.iterations, iteration);
}

void ApplyMotionRamp(const JointTrainerOptions& o, int64_t iteration,
                     LoopModel* model) {
  if (model->motion) {
    model->motion->SetDisplacementFactor(MotionRamp(o, iteration));
  }
}

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

LoopModel InitialLoopModel(const JointTrainerOptions& o, int num_frames,
                           GaussianSet initial,
                           std::optional<MotionField> motion,
                           std::mt19937_64* rng) {
  CHECK_GT(o.cycle_length, 0);
  initial.CheckConsistent();
  LoopModel model;
  model.gaussians = std::move(initial);
  model.cycle_length = o.cycle_length;
  FollowDynamicSet(o, DynamicSet(model.gaussians, o.dynamic_threshold), rng,
                   &model);
  Eigen::Vector3d lo, hi;
  FieldBox(model.gaussians, model.dynamic_index, &lo, &hi);
  if (o.use_motion) {
    if (motion) {
      model.motion.emplace(std::move(*motion));
      lo = model.motion->triplane().box_min();
      hi = model.motion->triplane().box_max();
    } else {
      model.motion.emplace(o.motion);
      model.motion->SetBox(lo, hi);
    }
  }
  if (o.use_residual) {
    ResidualFieldOptions r = o.residual;
    r.cycle_length = o.cycle_length;
    r.max_cycles = CyclesCovering(num_frames, o.cycle_length);
    model.residual.emplace(r);
    model.residual->SetBox(lo, hi);
  }
  if (model.motion) model.motion->set_mlp_precision(o.motion_precision);
  if (model.residual) model.residual->set_mlp_precision(o.residual_precision);
  return model;
}

bool DynamicSetRefreshDue(const JointTrainerOptions& o, int64_t iteration) {
  CHECK_GT(o.refresh_interval, 0);
  return iteration > 0 && iteration % o.refresh_interval == 0;
}

void FollowDynamicSet(const JointTrainerOptions& o, std::vector<int> next,
                      std::mt19937_64* rng, LoopModel* model) {
  std::vector<int> times(next.size());
  const std::vector<int>& index = model->dynamic_index;
  size_t old = 0;
  for (size_t k = 0; k < next.size(); ++k) {
    while (old < index.size() && index[old] < next[k]) ++old;
    if (old < index.size() && index[old] == next[k]) {
      times[k] = model->start_times[old];
    } else {
      times[k] = o.random_start ? DrawStartTime(o.cycle_length, rng) : 0;
    }
  }
  model->dynamic_index = std::move(next);
  model->start_times = std::move(times);
}

std::vector<double> FieldLearningRates(const JointTrainerOptions& o,
                                       int64_t iteration,
                                       const LoopModel& model) {
  auto decayed = [&o, iteration](double initial) {
    return LogLinearLr(initial, initial * o.field_lr_final_factor, iteration,
                       o.iterations);
  };
  std::vector<double> lr;
  if (model.motion) {
    lr.push_back(decayed(o.lr_motion_triplane));
    lr.push_back(decayed(o.lr_motion_mlp));
  }
  if (model.residual) {
    lr.push_back(decayed(o.lr_residual_triplane));
    lr.push_back(decayed(o.lr_residual_mlp));
  }
  return lr;
}

std::vector<std::vector<double>*> FieldParamBlocks(LoopModel* model) {
  std::vector<std::vector<double>*> blocks;
  if (model->motion) {
    blocks.push_back(&model->motion->triplane_params());
    blocks.push_back(&model->motion->mlp_params());
  }
  if (model->residual) {
    blocks.push_back(&model->residual->triplane_params());
    blocks.push_back(&model->residual->mlp_params());
  }
  return blocks;
}

std::vector<GuardedBlock> GuardedJointBlocks(const JointTrainerOptions& o,
                                             const LoopModel& model,
                                             double extent) {
  const JointLearningRateFlags& flags = o.lr_flags;
  std::vector<GuardedBlock> blocks =
      GuardedSplatBlocks(model.gaussians, extent, o.splat_lr, flags.splat);
  // Field values are of order one (MLP weights, triplane features around
  // 0 or 1).
  auto add = [&blocks](const std::string& field, const std::string& flag,
                       double rate, const double* values, int n) {
    blocks.push_back({field, field + " learning rate", flag, rate,
                      RunawayBound(values, n, 1.0)});
  };
  // A field's triplane, then its MLP.
  auto add_field = [&add](const std::string& name, const auto& field,
                          const std::string& triplane_flag,
                          double triplane_rate, const std::string& mlp_flag,
                          double mlp_rate) {
    add(name + "'s triplane", triplane_flag, triplane_rate,
        field.params().triplane, field.triplane().num_params());
    add(name + "'s MLP", mlp_flag, mlp_rate, field.params().mlp,
        field.mlp().num_params());
  };
  if (model.motion) {
    add_field("V", *model.motion, flags.motion_triplane, o.lr_motion_triplane,
              flags.motion_mlp, o.lr_motion_mlp);
  }
  if (model.residual) {
    add_field("D", *model.residual, flags.residual_triplane,
              o.lr_residual_triplane, flags.residual_mlp, o.lr_residual_mlp);
  }
  return blocks;
}

bool WaterDensifyDue(const JointTrainerOptions& o, int64_t iteration,
                     int num_dynamic) {
  const WaterDensifyOptions& d = o.water_densify;
  return d.interval > 0 && iteration % d.interval == 0 &&
         iteration <= o.iterations / 2 && num_dynamic > 0;
}

int WaterBudget(const JointTrainerOptions& o, int initial_dynamic) {
  return static_cast<int>(o.water_densify.max_growth * initial_dynamic);
}

std::vector<int> WaterDensifyViews(const JointTrainerOptions& o,
                                   const std::vector<int>& train,
                                   int64_t iteration) {
  const WaterDensifyOptions& d = o.water_densify;
  const int n = static_cast<int>(train.size());
  const int views = std::min(d.views, n);
  const int offset = static_cast<int>(iteration / d.interval);
  std::vector<int> frames;
  for (int k = 0; k < views; ++k)
    frames.push_back(train[(k * n / views + offset) % n]);
  return frames;
}

WaterDensifyResult DensifyRankedWater(const JointTrainerOptions& o,
                                      std::vector<double> mean_grad,
                                      int budget, int64_t iteration,
                                      const std::vector<Frame>& frames,
                                      const std::vector<int>& train,
                                      LoopModel* model, GaussianAdam* adam) {
  for (double& g : mean_grad)
    if (!std::isfinite(g)) g = 0.0;
  const WaterDensifyOptions& d = o.water_densify;
  const std::vector<int> picked =
      PickWaterToDensify(model->dynamic_index, mean_grad, d.fraction, budget);
  if (picked.empty()) return {};
  const std::vector<double> split_scale = PixelSizeInWorld(
      model->gaussians, picked, frames, train, d.split_pixels);
  std::seed_seq seq{static_cast<uint32_t>(o.seed),
                    static_cast<uint32_t>(o.seed >> 32),
                    static_cast<uint32_t>(iteration),
                    static_cast<uint32_t>(iteration >> 32), 0x57u};
  std::mt19937_64 rng(seq);
  const int child_cycle_length =
      o.random_start && d.fresh_start_times ? o.cycle_length : 0;
  return DensifyWater(picked, split_scale, child_cycle_length, &rng, model,
                      adam);
}

JointCheckpoint PackJointCheckpoint(
    const LoopModel& model, int64_t iteration, GaussianAdamState adam,
    std::vector<std::vector<double>> field_m,
    std::vector<std::vector<double>> field_v, int64_t field_step,
    FrameSampler::State sampler, const std::mt19937_64& rng) {
  JointCheckpoint c;
  c.iteration = iteration;
  c.gaussians = model.gaussians;
  c.adam = std::move(adam);
  c.dynamic_index = model.dynamic_index;
  c.start_times = model.start_times;
  auto append = [&c](const FieldParams& p, const Triplane& t, const Mlp& m) {
    c.field_params.emplace_back(p.triplane, p.triplane + t.num_params());
    c.field_params.emplace_back(p.mlp, p.mlp + m.num_params());
  };
  if (model.motion) {
    append(model.motion->params(), model.motion->triplane(),
           model.motion->mlp());
  }
  if (model.residual) {
    append(model.residual->params(), model.residual->triplane(),
           model.residual->mlp());
  }
  c.field_m = std::move(field_m);
  c.field_v = std::move(field_v);
  if (model.motion) AppendBox(model.motion->triplane(), &c.field_boxes);
  if (model.residual) AppendBox(model.residual->triplane(), &c.field_boxes);
  c.field_step = field_step;
  c.sampler = std::move(sampler);
  c.rng = RngState(rng);
  return c;
}

void UnpackJointCheckpoint(const JointCheckpoint& c, const std::string& source,
                           LoopModel* model) {
  std::vector<std::vector<double>*> blocks = FieldParamBlocks(model);
  bool match = c.field_params.size() == blocks.size() &&
               c.gaussians.sh_degree == model->gaussians.sh_degree;
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
  model->gaussians = c.gaussians;
  model->dynamic_index = c.dynamic_index;
  model->start_times = c.start_times;
  for (size_t b = 0; b < blocks.size(); ++b) *blocks[b] = c.field_params[b];
  auto box = [&c](int field, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
    *lo = Eigen::Vector3d(&c.field_boxes[6 * field]);
    *hi = Eigen::Vector3d(&c.field_boxes[6 * field + 3]);
  };
  Eigen::Vector3d lo, hi;
  int field = 0;
  if (model->motion) {
    box(field++, &lo, &hi);
    model->motion->SetBox(lo, hi);
  }
  if (model->residual) {
    box(field++, &lo, &hi);
    model->residual->SetBox(lo, hi);
  }
}

void RestoreSamplerAndRng(const JointCheckpoint& c, const std::string& source,
                          FrameSampler* sampler, std::mt19937_64* rng) {
  try {
    sampler->Restore(c.sampler);
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  if (!RestoreRngState(c.rng, rng))
    throw InputError(source + ": bad RNG state in checkpoint");
}

LoopModel FinalLoopModel(LoopModel model, const std::vector<Frame>& frames,
                         int* pruned) {
  // Every frame of the video, registered by COLMAP or not.
  int video_frames = 0;
  for (const Frame& f : frames)
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
