// Stage 3: joint training of the canonical splats, the motion field V and
// the residual field D on a scene, from the static model (es_static) and
// the pretrained V (es_flowinit).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "core/fields/field_io.h"
#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/flow/scene_flow_io.h"
#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "core/base/stage_profile.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/train/joint_trainer.h"
#include "solvers/train/training_history.h"
#include "solvers/train/water_particles.h"

DEFINE_string(scene, "", "Scene directory (images/, masks/, sparse/0/).");
DEFINE_string(init, "",
              "Directory with static.ply (es_static) and, optionally, "
              "motion_field.bin (es_flowinit).");
DEFINE_string(out, "", "Output model directory (created).");
DEFINE_int32(iterations, 20000, "Joint training iterations.");
DEFINE_string(device, "cpu", es::kDeviceFlagHelp);
DEFINE_bool(profile, false,
            "Print where the training iterations' wall time goes, per stage "
            "(projection, tiles, losses, Adam, fields, Euler chain, "
            "composition), after the last iteration.");
DEFINE_int32(cycle_length, 15,
             "Loop length L in frames (at most the number of frames).");
DEFINE_bool(resume, false,
            "Continue from <out>/joint_checkpoint.bin if it exists.");
DEFINE_int32(checkpoint_interval, 1000,
             "Write <out>/joint_checkpoint.bin every this many iterations "
             "(0: never).");
DEFINE_int32(log_interval, 100,
             "Print progress and add a row to <out>/history.csv every this "
             "many iterations (0: neither).");
DEFINE_int32(eval_interval, 1000,
             "Measure held-out PSNR into <out>/history.csv every this many "
             "iterations (and at the end; 0: only at the end).");
DEFINE_uint64(seed, 0, "Seed of frame sampling and loop start times.");
DEFINE_double(image_scale, 1.0, "Resize frames (and intrinsics) by this.");
DEFINE_bool(no_motion_field, false,
            "Ablation: no V; dynamic Gaussians move only through D.");
DEFINE_bool(no_flow_init, false,
            "Ablation: V from scratch even if motion_field.bin exists.");
DEFINE_bool(no_residual, false, "Ablation: no residual field D.");
DEFINE_bool(no_random_start, false,
            "Ablation: every loop starts at frame 0 (all reborn together).");
DEFINE_bool(static_only, false,
            "Comparison: no V and no D, only the splats are optimized.");
DEFINE_double(dynamic_threshold, 0.2,
              "A Gaussian is dynamic when sigmoid(dynamic_logit) exceeds "
              "this.");
DEFINE_int32(refresh_interval, 10,
             "Re-derive the dynamic set every this many iterations.");
DEFINE_double(ssim_weight, 0.2, "SSIM share of the photometric loss.");
DEFINE_double(mask_weight, 0.5, "Mask BCE weight (0: off).");
DEFINE_double(residual_weight, 0.01,
              "Weight of the residual L2 term (mean squared D outputs): "
              "keeps D from fitting each training frame's stochastic "
              "detail.");
DEFINE_double(lr_means, 1.6e-5,
              "Initial position learning rate (times the scene extent).");
DEFINE_double(lr_means_final, 1.6e-6, "Final position learning rate.");
DEFINE_double(lr_log_scales, 5e-3, "Log-scale learning rate.");
DEFINE_double(lr_quats, 1e-3, "Rotation learning rate.");
DEFINE_double(lr_opacity, 0.05, "Opacity-logit learning rate.");
DEFINE_double(lr_sh_dc, 2.5e-3, "SH DC learning rate.");
DEFINE_double(lr_sh_rest, 1.25e-4, "Higher SH bands learning rate.");
DEFINE_double(lr_dynamic, 0.05, "Dynamic-logit learning rate.");
DEFINE_double(lr_motion_triplane, 5e-4,
              "V triplane learning rate (fine-tuning the flow-initialized "
              "field: 10x lower measured better PSNR and motion error).");
DEFINE_double(lr_motion_mlp, 1e-4, "V MLP learning rate.");
DEFINE_double(lr_residual_triplane, 5e-3, "D triplane learning rate.");
DEFINE_double(lr_residual_mlp, 1e-3, "D MLP learning rate.");
DEFINE_double(field_lr_final_factor, 0.1,
              "Field learning rates decay log-linearly to this factor.");
DEFINE_int32(motion_resolution, 128, "V triplane resolution (from scratch).");
DEFINE_int32(motion_channels, 12, "V triplane channels (from scratch).");
DEFINE_int32(motion_width, 64, "V MLP width (from scratch).");
DEFINE_int32(motion_depth, 2, "V MLP hidden layers (from scratch).");
DEFINE_int32(residual_resolution, 128, "D triplane resolution.");
DEFINE_int32(residual_channels, 16, "D triplane channels.");
DEFINE_int32(residual_width, 128, "D MLP width.");
DEFINE_int32(residual_depth, 2, "D MLP hidden layers.");
DEFINE_int32(residual_cycle_frequencies, 4,
             "Frequencies of D's cycle-number encoding. 0: D depends on the "
             "cycle index only, so it is periodic and the loop shows exactly "
             "what training fits (with > 0 the loop evaluates every "
             "Gaussian's D at cycle number 0, which each Gaussian saw in a "
             "different stretch of the video).");
DEFINE_bool(white_background, false, "Render on white instead of black.");
DEFINE_double(particle_pixels, 0,
              "> 0: before training, split every water Gaussian larger "
              "than this (std dev in pixels on screen) into particles of "
              "this size drawn from its volume; 0: keep the static "
              "model's water as it is.");
DEFINE_int32(max_particle_children, 16,
             "Most particles one water Gaussian is split into.");
DEFINE_int32(max_particles, 20000,
             "Most water Gaussians after the particle split.");
DEFINE_double(max_dynamic_pixels, 0,
              "> 0: keep water Gaussians at most this large on screen (std "
              "dev in pixels) during training; 0: no limit.");
DEFINE_double(flow_prior_weight, 1,
              "> 0: keep Stage 2's lifted scene-flow samples "
              "(<init>/scene_flow_samples.bin, written by es_flowinit) as a "
              "loss on V during joint training, with this weight at the "
              "start (relative to the mean squared sample speed); 0: off.");
DEFINE_double(flow_prior_final_factor, 0.1,
              "The scene-flow prior's weight decays log-linearly to this "
              "fraction of --flow_prior_weight by the last iteration.");
DEFINE_bool(flow_prior_to_field, false,
            "Hold V to Stage 2's own V (<init>/motion_field.bin) at the "
            "samples' points, every direction of it, instead of to the "
            "lifted samples.");
DEFINE_int32(flow_prior_batch, 1024,
             "Scene-flow samples per iteration for the prior.");
DEFINE_int32(densify_water_interval, 50,
             "> 0: every this many iterations of the first half, split or "
             "clone the water Gaussians the images disagree with most "
             "(mean view-space gradient); 0: off.");
DEFINE_double(densify_water_fraction, 0.2,
              "Fraction of the water Gaussians densified each time, "
              "highest gradient first.");
DEFINE_double(densify_water_growth, 3,
              "Densification stops at this many times the water Gaussians "
              "joint training starts with (training time grows with them).");
DEFINE_int32(densify_water_views, 8,
             "Training frames whose gradients rank the water Gaussians.");
DEFINE_double(densify_water_split_pixels, 1.0,
              "Water Gaussians larger than this on screen (std dev, px) are "
              "split in two smaller ones, smaller ones cloned.");
DEFINE_bool(densify_water_fresh_start, true,
            "Densified water Gaussians draw their own random start times "
            "(off: they keep their parent's, which piles a lineage's loop "
            "wraps onto one frame step).");
DEFINE_double(motion_energy_weight, 1,
              "> 0: each iteration also renders the sampled frame's "
              "neighbour in the video and matches the local amplitude of "
              "frame-to-frame change in the water, per colour channel, to "
              "the input's, with this weight (the L1 / SSIM loss alone is "
              "lowest for a still, time-averaged sheet); 0: off. Twice the "
              "rendering per iteration.");
DEFINE_double(detail_energy_weight, 1,
              "> 0: with the same frame pairs, match the local amplitude "
              "of the water's fine texture (each colour channel minus its "
              "blur) to the input's, with this weight; 0: off.");
DEFINE_int32(detail_energy_octaves, 1,
             "Bands of the detail energy, finest first, each twice the "
             "scale of the last (a difference-of-Gaussians pyramid): 1 "
             "matches texture of about a pixel; 3 also a few pixels wide "
             "(puffs, gaps, droplet clusters).");
DEFINE_double(texture_weight, 0,
              "> 0: with the same frame pairs, match the distribution of "
              "the water's texture in each frame to the input frame's "
              "(sliced Wasserstein distance between the water pixels' "
              "band neighbourhoods, wherever each streak is), with this "
              "weight; 0: off. About 1.7x the joint time at 160x120 (3 is "
              "the weight docs/results/realism-2026-12-04.md measured). On "
              "--device cuda it runs on the host.");
DEFINE_double(loop_texture_weight, 3,
              "> 0: also render each sampled frame as the loop plays it "
              "(every water Gaussian at cycle number 0, as es_animate "
              "shows it) and match its water's texture to the input "
              "frame's with this weight (the texture term's bands and "
              "projections); 0: off, and about 1.7x faster joint "
              "iterations. "
              "Training fits each frame at its own cycle numbers; this "
              "scores the frames the loop shows "
              "(docs/results/realism-2026-12-04.md: every "
              "preset's loop closer to the video). Its loss runs on the "
              "host, so on --device cuda it is off unless given.");
DEFINE_int32(texture_bands, 2,
             "Bands of the texture term's difference-of-Gaussians "
             "pyramid, finest first, each twice the scale of the last.");
DEFINE_int32(texture_projections, 16,
             "Random directions of the texture term's sliced distance, "
             "new ones each iteration.");

namespace es {
namespace {

namespace fs = std::filesystem;

void Require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

JointTrainerOptions OptionsFromFlags() {
  RequireFlag("scene", FLAGS_scene);
  RequireFlag("init", FLAGS_init);
  RequireFlag("out", FLAGS_out);
  RequireAtLeast("iterations", FLAGS_iterations, 0);
  RequireAtLeast("cycle_length", FLAGS_cycle_length, 1);
  RequireAtLeast("refresh_interval", FLAGS_refresh_interval, 1);
  RequireAtLeast("checkpoint_interval", FLAGS_checkpoint_interval, 0);
  RequireAtLeast("log_interval", FLAGS_log_interval, 0);
  RequireAtLeast("eval_interval", FLAGS_eval_interval, 0);
  RequirePositive("image_scale", FLAGS_image_scale);
  RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  RequireInRange("ssim_weight", FLAGS_ssim_weight, 0, 1);
  RequireNonNegative("mask_weight", FLAGS_mask_weight);
  RequireNonNegative("residual_weight", FLAGS_residual_weight);
  RequireInRange("field_lr_final_factor", FLAGS_field_lr_final_factor, 0, 1);
  Require(FLAGS_lr_means_final <= FLAGS_lr_means,
          "--lr_means_final must not exceed --lr_means");
  RequireAtLeast("motion_resolution", FLAGS_motion_resolution, 2);
  RequireAtLeast("residual_resolution", FLAGS_residual_resolution, 2);
  RequireAtLeast("motion_channels", FLAGS_motion_channels, 1);
  RequireAtLeast("residual_channels", FLAGS_residual_channels, 1);
  RequireAtLeast("motion_width", FLAGS_motion_width, 1);
  RequireAtLeast("residual_width", FLAGS_residual_width, 1);
  RequireAtLeast("motion_depth", FLAGS_motion_depth, 0);
  RequireAtLeast("residual_depth", FLAGS_residual_depth, 0);
  RequireAtLeast("residual_cycle_frequencies",
                 FLAGS_residual_cycle_frequencies, 0);
  RequireNonNegative("particle_pixels", FLAGS_particle_pixels);
  RequireNonNegative("max_dynamic_pixels", FLAGS_max_dynamic_pixels);
  RequireAtLeast("max_particle_children", FLAGS_max_particle_children, 1);
  RequireAtLeast("max_particles", FLAGS_max_particles, 1);
  RequireNonNegative("flow_prior_weight", FLAGS_flow_prior_weight);
  RequireNonNegative("motion_energy_weight", FLAGS_motion_energy_weight);
  RequireNonNegative("detail_energy_weight", FLAGS_detail_energy_weight);
  RequireInRange("detail_energy_octaves", FLAGS_detail_energy_octaves, 1, 8);
  RequireNonNegative("texture_weight", FLAGS_texture_weight);
  RequireNonNegative("loop_texture_weight", FLAGS_loop_texture_weight);
  RequireInRange("texture_bands", FLAGS_texture_bands, 1, 6);
  RequireInRange("texture_projections", FLAGS_texture_projections, 1, 1024);
  RequireInRange("flow_prior_final_factor", FLAGS_flow_prior_final_factor, 0,
                 1);
  RequireAtLeast("flow_prior_batch", FLAGS_flow_prior_batch, 1);
  RequireAtLeast("densify_water_interval", FLAGS_densify_water_interval, 0);
  RequireInRange("densify_water_fraction", FLAGS_densify_water_fraction, 0,
                 1);
  RequireInRange("densify_water_growth", FLAGS_densify_water_growth, 1, 1000);
  RequireAtLeast("densify_water_views", FLAGS_densify_water_views, 1);
  RequirePositive("densify_water_split_pixels",
                  FLAGS_densify_water_split_pixels);
  JointTrainerOptions o;
  o.iterations = FLAGS_iterations;
  o.seed = FLAGS_seed;
  o.cycle_length = FLAGS_cycle_length;
  o.use_motion = !FLAGS_no_motion_field && !FLAGS_static_only;
  o.use_residual = !FLAGS_no_residual && !FLAGS_static_only;
  o.random_start = !FLAGS_no_random_start;
  o.dynamic_threshold = FLAGS_dynamic_threshold;
  o.refresh_interval = FLAGS_refresh_interval;
  o.ssim_weight = FLAGS_ssim_weight;
  o.mask_weight = FLAGS_mask_weight;
  o.residual_weight = FLAGS_residual_weight;
  o.splat_lr.means_initial = FLAGS_lr_means;
  o.splat_lr.means_final = FLAGS_lr_means_final;
  o.splat_lr.log_scales = FLAGS_lr_log_scales;
  o.splat_lr.quats = FLAGS_lr_quats;
  o.splat_lr.opacity = FLAGS_lr_opacity;
  o.splat_lr.sh_dc = FLAGS_lr_sh_dc;
  o.splat_lr.sh_rest = FLAGS_lr_sh_rest;
  o.splat_lr.dynamic = FLAGS_lr_dynamic;
  o.lr_motion_triplane = FLAGS_lr_motion_triplane;
  o.lr_motion_mlp = FLAGS_lr_motion_mlp;
  o.lr_residual_triplane = FLAGS_lr_residual_triplane;
  o.lr_residual_mlp = FLAGS_lr_residual_mlp;
  o.field_lr_final_factor = FLAGS_field_lr_final_factor;
  o.max_dynamic_pixels = FLAGS_max_dynamic_pixels;
  o.flow_prior.weight = FLAGS_flow_prior_weight;
  o.flow_prior.final_factor = FLAGS_flow_prior_final_factor;
  o.flow_prior.batch_size = FLAGS_flow_prior_batch;
  o.water_densify.interval = FLAGS_densify_water_interval;
  o.water_densify.fraction = FLAGS_densify_water_fraction;
  o.water_densify.max_growth = FLAGS_densify_water_growth;
  o.water_densify.views = FLAGS_densify_water_views;
  o.water_densify.split_pixels = FLAGS_densify_water_split_pixels;
  o.water_densify.fresh_start_times = FLAGS_densify_water_fresh_start;
  o.water_energy.motion_weight = FLAGS_motion_energy_weight;
  o.water_energy.detail_weight = FLAGS_detail_energy_weight;
  o.water_energy.detail_octaves = FLAGS_detail_energy_octaves;
  o.water_texture.weight = FLAGS_texture_weight;
  o.loop_texture_weight = FLAGS_loop_texture_weight;
  o.water_texture.bands = FLAGS_texture_bands;
  o.water_texture.projections = FLAGS_texture_projections;
  o.motion.triplane.resolution = FLAGS_motion_resolution;
  o.motion.triplane.channels = FLAGS_motion_channels;
  o.motion.mlp_width = FLAGS_motion_width;
  o.motion.mlp_depth = FLAGS_motion_depth;
  o.residual.triplane.resolution = FLAGS_residual_resolution;
  o.residual.triplane.channels = FLAGS_residual_channels;
  o.residual.mlp_width = FLAGS_residual_width;
  o.residual.mlp_depth = FLAGS_residual_depth;
  o.residual.p_frequencies = FLAGS_residual_cycle_frequencies;
  if (FLAGS_white_background) o.background.setOnes();
  return o;
}

void WriteMetrics(const std::string& path, const LoopMetrics& m,
                  double seconds, int64_t iterations, const LoopModel& model,
                  bool flow_init, double final_loss) {
  WriteJsonFile(path, {{"psnr_test", m.psnr},
                       {"ssim_test", m.ssim},
                       {"psnr_test_water", m.psnr_water},
                       {"ssim_test_water", m.ssim_water},
                       {"test_frames", m.frames},
                       {"seconds", seconds},
                       {"iterations", iterations},
                       {"num_gaussians", model.gaussians.size()},
                       {"num_dynamic", model.num_dynamic()},
                       {"cycle_length", model.cycle_length},
                       {"motion_field", model.motion.has_value()},
                       {"flow_init", flow_init},
                       {"residual_field", model.residual.has_value()},
                       {"random_start", !FLAGS_no_random_start},
                       {"final_loss", final_loss}});
}

// Stage 2's V, written by es_flowinit beside the static model.
std::string InitMotionFieldPath() {
  return (fs::path(FLAGS_init) / "motion_field.bin").string();
}

// V pretrained by es_flowinit (<init>/motion_field.bin) when there is one
// and it is wanted; nullopt starts V from scratch.
std::optional<MotionField> PretrainedMotion(const JointTrainerOptions& options,
                                            bool* flow_init) {
  *flow_init = false;
  if (!options.use_motion) return std::nullopt;
  const std::string path = InitMotionFieldPath();
  if (FLAGS_no_flow_init) {
    std::printf("V: from scratch (--no_flow_init)\n");
    return std::nullopt;
  }
  if (!fs::exists(path)) {
    std::printf("V: from scratch (%s not found)\n", path.c_str());
    return std::nullopt;
  }
  *flow_init = true;
  std::printf("V: pretrained from %s\n", path.c_str());
  return LoadMotionField(path);
}

// Gives the trainer Stage 2's samples as a prior on V when one is wanted
// and V was pretrained from them.
void AddFlowPrior(const JointTrainerOptions& options, bool flow_init,
                  JointStageTrainer* trainer) {
  if (options.flow_prior.weight <= 0 || !options.use_motion) return;
  const std::string path =
      (fs::path(FLAGS_init) / "scene_flow_samples.bin").string();
  if (!flow_init || !fs::exists(path)) {
    std::printf("scene-flow prior: off (%s)\n",
                flow_init ? (path + " not found").c_str()
                          : "V is not pretrained");
    return;
  }
  std::vector<SceneFlowSample> samples = LoadSceneFlowSamples(path);
  if (samples.empty()) {
    std::printf("scene-flow prior: off (%s holds no samples)\n",
                path.c_str());
    return;
  }
  if (FLAGS_flow_prior_to_field) {
    TargetFieldAtSamples(LoadMotionField(InitMotionFieldPath()), &samples);
  }
  std::printf("scene-flow prior: %zu %s from %s, weight %g -> %g\n",
              samples.size(),
              FLAGS_flow_prior_to_field ? "points of Stage 2's V" : "samples",
              path.c_str(), options.flow_prior.weight,
              options.flow_prior.weight * options.flow_prior.final_factor);
  trainer->SetSceneFlowPrior(std::move(samples));
}

// Splits the static model's large water Gaussians into particles
// (--particle_pixels > 0).
void SplitWater(const JointTrainerOptions& options, const Scene& scene,
                GaussianSet* gaussians) {
  if (FLAGS_particle_pixels <= 0) return;
  WaterParticleOptions particles;
  particles.particle_pixels = FLAGS_particle_pixels;
  particles.max_children = FLAGS_max_particle_children;
  particles.max_particles = FLAGS_max_particles;
  particles.dynamic_threshold = options.dynamic_threshold;
  particles.seed = FLAGS_seed;
  const ParticleSplitStats split = SplitWaterIntoParticles(
      particles, scene.frames, scene.train, gaussians);
  std::printf("water split into particles: %d blobs -> %d particles "
              "(water Gaussians %d -> %d)\n",
              split.blobs, split.particles, split.dynamic_before,
              split.dynamic_after);
}

// The history.csv columns after the iteration and time.
const std::vector<std::string> kHistoryColumns = {
    "loss",      "photometric", "mask",      "residual",
    "gaussians", "dynamic",     "psnr_test", "psnr_test_water"};

// What Train leaves for the end of the run.
struct TrainingOutcome {
  double seconds = 0;       // this session's training time, evaluations not
  double final_loss = NAN;  // mean loss of the last logged interval
  // The last history row, still without the final metrics (empty when the
  // run had nothing left to log).
  std::vector<double> final_row;
};

// Runs the trainer to options.iterations with progress lines (ETA, held-out
// PSNR every --eval_interval), history rows and periodic checkpoints.
TrainingOutcome Train(const JointTrainerOptions& options, const Scene& scene,
                      const std::string& checkpoint_path,
                      double seconds_before, TrainingHistory* history,
                      JointStageTrainer* trainer) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  double eval_seconds = 0;  // kept out of the training clock
  const auto training_seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - start).count() -
           eval_seconds;
  };
  const int64_t first = trainer->iteration();
  int64_t last_row = first;
  // loss, photometric, mask, residual, motion and detail energy, texture,
  // the loop's texture
  double sums[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int64_t counted = 0;             // steps in the sums
  TrainingOutcome outcome;
  StageProfile::Get().Start(FLAGS_profile);
  while (trainer->iteration() < options.iterations) {
    const JointIterationStats s = trainer->Step();
    if (!s.skipped) {  // a skipped step's loss is not finite
      sums[0] += s.loss;
      sums[1] += s.photometric;
      sums[2] += s.mask;
      sums[3] += s.residual;
      sums[4] += s.energy.motion;
      sums[5] += s.energy.detail;
      sums[6] += s.texture;
      sums[7] += s.loop_texture;
      ++counted;
    }
    const int64_t it = trainer->iteration();
    if (s.densified.split + s.densified.cloned > 0) {
      std::printf("iter %lld: water densified, %d split, %d cloned (water "
                  "Gaussians %d)\n",
                  static_cast<long long>(it), s.densified.split,
                  s.densified.cloned, trainer->model().num_dynamic());
    }
    const bool log =
        FLAGS_log_interval > 0 &&
        (it % FLAGS_log_interval == 0 || it == options.iterations);
    const bool eval = FLAGS_eval_interval > 0 &&
                      it % FLAGS_eval_interval == 0 &&
                      it < options.iterations;  // the end is in Run
    if (log || eval) {
      const double window = counted > 0 ? counted : NAN;
      outcome.final_loss = sums[0] / window;
      const double elapsed = training_seconds();
      LoopMetrics held_out;
      if (eval) {
        const Clock::time_point eval_start = Clock::now();
        held_out = EvaluateLoopModel(trainer->model(), scene.frames,
                                     scene.test, trainer->render_options());
        eval_seconds +=
            std::chrono::duration<double>(Clock::now() - eval_start).count();
      }
      const std::vector<double> row = {
          sums[0] / window,
          sums[1] / window,
          sums[2] / window,
          sums[3] / window,
          static_cast<double>(trainer->model().gaussians.size()),
          static_cast<double>(s.num_dynamic),
          eval ? held_out.psnr : NAN,
          eval ? held_out.psnr_water : NAN};
      if (it < options.iterations) {
        history->Add(it, seconds_before + elapsed, row);
        history->Write();
      } else {
        outcome.final_row = row;  // completed with the final metrics
      }
      const double rate = (it - first) / std::max(elapsed, 1e-9);
      std::printf(
          "iter %lld/%d  loss %.5f (photo %.5f mask %.5f res %.2e)  "
          "dynamic %d  %.2f it/s  ETA %.0f s",
          static_cast<long long>(it), options.iterations, outcome.final_loss,
          sums[1] / window, sums[2] / window, sums[3] / window,
          s.num_dynamic, rate, (options.iterations - it) / rate);
      if (options.water_energy.motion_weight > 0 ||
          options.water_energy.detail_weight > 0) {
        std::printf("  energy motion %.4f detail %.4f", sums[4] / window,
                    sums[5] / window);
      }
      if (options.water_texture.weight > 0)
        std::printf("  texture %.5f", sums[6] / window);
      if (options.loop_texture_weight > 0)
        std::printf("  loop texture %.5f", sums[7] / window);
      if (eval) std::printf("  held-out PSNR %.2f dB", held_out.psnr);
      std::printf("\n");
      std::fflush(stdout);
      last_row = it;
      for (double& v : sums) v = 0;
      counted = 0;
    }
    // Not right after a skipped (non-finite) step: keep the last good one.
    if (FLAGS_checkpoint_interval > 0 &&
        it % FLAGS_checkpoint_interval == 0 && trainer->last_step_ok()) {
      WriteJointCheckpoint(trainer->Save(), checkpoint_path);
    }
  }
  outcome.seconds = training_seconds();
  if (trainer->skipped_steps() > 0)
    std::printf("%lld step(s) skipped for a non-finite loss or gradient\n",
                static_cast<long long>(trainer->skipped_steps()));
  StageProfile::Get().PrintAndStop(
      "es_train, " + std::to_string(trainer->iteration() - first) +
      " iterations, " + std::to_string(trainer->model().gaussians.size()) +
      " Gaussians, " + std::to_string(trainer->model().num_dynamic()) +
      " dynamic");
  if (outcome.final_row.empty() && trainer->iteration() > last_row) {
    const double window = counted > 0 ? counted : NAN;
    outcome.final_row = {
        sums[0] / window,
        sums[1] / window,
        sums[2] / window,
        sums[3] / window,
        static_cast<double>(trainer->model().gaussians.size()),
        static_cast<double>(trainer->model().num_dynamic()),
        NAN,
        NAN};
  }
  return outcome;
}

// The last history row carries the final model's held-out metrics.
void RecordFinalMetrics(const LoopMetrics& metrics, int64_t iteration,
                        double seconds, std::vector<double> final_row,
                        TrainingHistory* history) {
  if (!final_row.empty()) {
    final_row[6] = metrics.psnr;
    final_row[7] = metrics.psnr_water;
    history->Add(iteration, seconds, final_row);
  } else {
    history->SetFinalMetrics(iteration, seconds,
                             {{"psnr_test", metrics.psnr},
                              {"psnr_test_water", metrics.psnr_water}});
  }
  history->Write();
}

int Run() {
  JointTrainerOptions options = OptionsFromFlags();
  std::string device_name;
  const ComputeDevice device = ParseDeviceFlag(FLAGS_device, &device_name);
  if (device == ComputeDevice::kCuda && options.loop_texture_weight > 0 &&
      gflags::GetCommandLineFlagInfoOrDie("loop_texture_weight").is_default) {
    // Its loss runs on the host: at the paper's resolution it would take
    // most of a GPU iteration.
    options.loop_texture_weight = 0;
    std::printf("--device cuda: the loop texture term is off unless "
                "--loop_texture_weight is given (its loss runs on the "
                "host)\n");
  }
  PrepareOutputDirectory(FLAGS_out, "out");
  SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const Scene scene = LoadScene(FLAGS_scene, scene_options);
  Require(!scene.train.empty(), FLAGS_scene + ": no training frames");
  // A loop longer than the video has frames no training image shows (and
  // its cost grows with L).
  RequireAtMost("cycle_length", FLAGS_cycle_length,
                static_cast<int64_t>(scene.frames.size()),
                FLAGS_scene + " has " + std::to_string(scene.frames.size()) +
                    " frames");
  const std::string static_ply = (fs::path(FLAGS_init) / "static.ply").string();
  GaussianSet initial = ReadPly(static_ply);
  Require(initial.size() > 0, static_ply + ": holds no Gaussians");
  std::printf("loaded %s: %d Gaussians, SH degree %d\n", static_ply.c_str(),
              initial.size(), initial.sh_degree);
  bool flow_init = false;
  std::optional<MotionField> motion = PretrainedMotion(options, &flow_init);
  SplitWater(options, scene, &initial);

  const std::unique_ptr<JointStageTrainer> trainer_on_device =
      JointTrainerOn(device)(&scene.frames, scene.train, options,
                             std::move(initial), std::move(motion));
  JointStageTrainer& trainer = *trainer_on_device;
  if (device == ComputeDevice::kCuda)
    std::printf("training on %s\n", device_name.c_str());
  AddFlowPrior(options, flow_init, &trainer);
  std::printf("dynamic Gaussians: %d of %d; V %s, D %s; masks %s\n",
              trainer.model().num_dynamic(), trainer.model().gaussians.size(),
              options.use_motion ? "on" : "off",
              options.use_residual ? "on" : "off",
              trainer.uses_masks() ? "on" : "off");
  const std::string checkpoint_path =
      (fs::path(FLAGS_out) / "joint_checkpoint.bin").string();
  if (FLAGS_resume && fs::exists(checkpoint_path)) {
    trainer.Restore(ReadJointCheckpoint(checkpoint_path), checkpoint_path);
    std::printf("resumed from %s at iteration %lld\n",
                checkpoint_path.c_str(),
                static_cast<long long>(trainer.iteration()));
  }
  TrainingHistory history((fs::path(FLAGS_out) / "history.csv").string(),
                          kHistoryColumns);
  const double seconds_before = history.Resume(trainer.iteration());
  const TrainingOutcome outcome = Train(options, scene, checkpoint_path,
                                        seconds_before, &history, &trainer);

  int pruned = 0;
  const LoopModel model = trainer.FinalModel(&pruned);
  std::printf("pruned %d invisible Gaussians (opacity < 1/255 in every "
              "frame)\n", pruned);
  SaveLoopModel(model, FLAGS_out);
  const LoopMetrics metrics = EvaluateLoopModel(
      model, scene.frames, scene.test, trainer.render_options());
  WriteMetrics((fs::path(FLAGS_out) / "metrics.json").string(), metrics,
               outcome.seconds, trainer.iteration(), model, flow_init,
               outcome.final_loss);
  RecordFinalMetrics(metrics, trainer.iteration(),
                     seconds_before + outcome.seconds, outcome.final_row,
                     &history);
  std::printf("test PSNR %.3f SSIM %.4f (water PSNR %.3f SSIM %.4f) over %d "
              "frames; %.1f s\n",
              metrics.psnr, metrics.ssim, metrics.psnr_water,
              metrics.ssim_water, metrics.frames, outcome.seconds);
  return 0;
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Stage 3: joint training of the looping model.\n"
                    "  es_train --scene DIR --init DIR --out DIR "
                    "[--iterations N] [--cycle_length L] [--resume]\n"
                    "           [--device cpu|cuda]\n"
                    "Writes the model (loop.txt, canonical.ply, fields), "
                    "<out>/metrics.json, <out>/history.csv and "
                    "<out>/joint_checkpoint.bin.",
                    es::Run);
}
