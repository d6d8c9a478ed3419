#include "apps/common/joint_flags.h"

#include <gflags/gflags.h>

#include <cstdio>
#include <string>

#include "apps/common/flag_checks.h"
#include "apps/common/splat_rate_flags.h"
#include "apps/common/world.h"
#include "core/base/parse_choice.h"

DEFINE_string(scene, "", "Scene directory (images/, masks/, sparse/0/).");
DEFINE_string(init, "",
              "Directory with static.ply (es_static) and, optionally, "
              "motion_field.bin (es_flowinit).");
DEFINE_string(out, "", "Output model directory (created).");
DEFINE_int32(iterations, 20000, "Joint training iterations.");
DEFINE_string(device, "cpu", es::kDeviceFlagHelp);
DEFINE_int32(batch_frames, 1, es::kBatchFramesHelp);
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
DEFINE_int32(loop_texture_interval, 1,
             "Score the loop's texture (--loop_texture_weight) only on "
             "every K-th iteration, at the weight times K: the same "
             "expected gradient for 1/K of the term's cost (~40% of a "
             "joint iteration at 1). 2: 12% less joint CPU time, 4: 27% "
             "less but the loop's water moves and looks less like the "
             "input (docs/RESULTS.md, \"The loop texture interval\"). 1: "
             "every iteration.");
DEFINE_double(input_noise, -1,
              "Std (0..1 of the pixel range) of the input frames' per-pixel "
              "noise (sensor or render-sample noise, new each frame), "
              "which the water losses then do not ask the render to paint: "
              "its expected share of the input's detail and change is "
              "added to the render's before they are compared. -1: "
              "estimated from consecutive training frames outside the "
              "water (printed when found; clean or 8-bit-only input gives "
              "none, and so do noise and camera motion that cannot be told "
              "apart); 0: none.");
DEFINE_double(water_loss_warmup, 0,
              "> 0: the water losses (energy, texture, the loop's texture) "
              "ramp in linearly from 0 over this fraction of the "
              "iterations, so Stage 3 first fits the frames with the water "
              "moving and then trades some fidelity for the input's detail "
              "and motion (docs/results/stage3-start.md); 0: at full "
              "weight from the first step.");
DEFINE_double(motion_warmup, 0,
              "> 0: V's displacement (each Euler step) ramps in linearly "
              "from 0 over this fraction of the iterations, so Stage 3 "
              "starts from Stage 1's model exactly instead of carrying its "
              "time-averaged water downstream from the first step "
              "(docs/results/stage3-start.md); 0: full steps from the start.");
DEFINE_string(motion_precision, "double",
              "Arithmetic of V's MLP in CPU training: double or float "
              "(twice the lanes per vector; the parameters, inputs and "
              "gradients stay double). --device cuda and the evaluation "
              "run it in double. V's MLP is small next to its triplane: "
              "float saves 5-8% of V's time (docs/BENCHMARKS.md, \"Fields "
              "in float\").");
DEFINE_string(residual_precision, "double",
              "Arithmetic of D's MLP in CPU training, as "
              "--motion_precision. float: D 1.5x faster (with V in float "
              "too, the whole run 4% faster), but the loop's water moved "
              "less like the input over three seeds (docs/BENCHMARKS.md, "
              "\"Fields in float\").");
DEFINE_int32(input_cache_mb, 128,
             "Memory (MB) each water loss may keep of what it computes "
             "from the input frames alone (the energy loss's input "
             "energies; the texture loss's water pixels, their "
             "neighbourhoods and bands), so a frame scored again skips "
             "that work; the same values either way. 0: nothing kept.");
DEFINE_int32(texture_bands, 2,
             "Bands of the texture term's difference-of-Gaussians "
             "pyramid, finest first, each twice the scale of the last.");
DEFINE_int32(texture_projections, 16,
             "Random directions of the texture term's sliced distance, "
             "new ones each iteration.");

namespace es {
namespace {

MlpPrecision ParsePrecision(const std::string& flag, const std::string& name) {
  return ParseChoice<MlpPrecision>(
      flag, name,
      {{"double", MlpPrecision::kDouble}, {"float", MlpPrecision::kFloat}});
}

// Throws InputError naming the flag for a value out of range.
void CheckFlags() {
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
  RequireAtLeast("loop_texture_interval", FLAGS_loop_texture_interval, 1);
  RequireInRange("input_noise", FLAGS_input_noise, -1, 1);
  RequireInRange("water_loss_warmup", FLAGS_water_loss_warmup, 0, 1);
  RequireInRange("motion_warmup", FLAGS_motion_warmup, 0, 1);
  RequireInRange("texture_bands", FLAGS_texture_bands, 1, 6);
  RequireAtLeast("input_cache_mb", FLAGS_input_cache_mb, 0);
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
}

JointTrainerOptions TrainerOptionsFromFlags() {
  JointTrainerOptions o;
  o.iterations = FLAGS_iterations;
  o.seed = FLAGS_seed;
  o.batch_frames = FLAGS_batch_frames;
  o.cycle_length = FLAGS_cycle_length;
  o.use_motion = !FLAGS_no_motion_field && !FLAGS_static_only;
  o.use_residual = !FLAGS_no_residual && !FLAGS_static_only;
  o.random_start = !FLAGS_no_random_start;
  o.dynamic_threshold = FLAGS_dynamic_threshold;
  o.refresh_interval = FLAGS_refresh_interval;
  o.ssim_weight = FLAGS_ssim_weight;
  o.mask_weight = FLAGS_mask_weight;
  o.residual_weight = FLAGS_residual_weight;
  o.splat_lr = SplatRatesFromFlags(
      {"lr_means", "lr_means_final", "lr_log_scales", "lr_quats"});
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
  o.loop_texture_interval = FLAGS_loop_texture_interval;
  o.water_loss_warmup = FLAGS_water_loss_warmup;
  o.motion_warmup = FLAGS_motion_warmup;
  o.water_texture.bands = FLAGS_texture_bands;
  o.water_texture.projections = FLAGS_texture_projections;
  o.water_energy.input_cache_bytes = size_t(FLAGS_input_cache_mb) << 20;
  o.water_texture.input_cache_bytes = size_t(FLAGS_input_cache_mb) << 20;
  o.motion.triplane.resolution = FLAGS_motion_resolution;
  o.motion.triplane.channels = FLAGS_motion_channels;
  o.motion.mlp_width = FLAGS_motion_width;
  o.motion.mlp_depth = FLAGS_motion_depth;
  o.residual.triplane.resolution = FLAGS_residual_resolution;
  o.residual.triplane.channels = FLAGS_residual_channels;
  o.residual.mlp_width = FLAGS_residual_width;
  o.residual.mlp_depth = FLAGS_residual_depth;
  o.residual.p_frequencies = FLAGS_residual_cycle_frequencies;
  o.motion_precision = ParsePrecision("--motion_precision",
                                      FLAGS_motion_precision);
  o.residual_precision = ParsePrecision("--residual_precision",
                                        FLAGS_residual_precision);
  if (FLAGS_white_background) o.background.setOnes();
  return o;
}

}  // namespace

JointStageOptions JointStageOptionsFromFlags(ComputeDevice* device) {
  CheckFlags();
  JointStageOptions o;
  o.trainer = TrainerOptionsFromFlags();
  std::string device_name;
  *device = ParseDeviceFlag(FLAGS_device, &device_name);
  if (*device == ComputeDevice::kCuda) {
    o.device_name = device_name;
    if (o.trainer.loop_texture_weight > 0 &&
        gflags::GetCommandLineFlagInfoOrDie("loop_texture_weight").is_default) {
      // Its loss runs on the host: at the paper's resolution it would take
      // most of a GPU iteration.
      o.trainer.loop_texture_weight = 0;
      std::printf("--device cuda: the loop texture term is off unless "
                  "--loop_texture_weight is given (its loss runs on the "
                  "host)\n");
    }
  }
  o.scene_dir = FLAGS_scene;
  o.init_dir = FLAGS_init;
  o.out_dir = FLAGS_out;
  o.scene.image_scale = FLAGS_image_scale;
  o.resume = FLAGS_resume;
  o.checkpoint_interval = FLAGS_checkpoint_interval;
  o.log_interval = FLAGS_log_interval;
  o.eval_interval = FLAGS_eval_interval;
  o.input_noise = FLAGS_input_noise;
  o.flow_init = !FLAGS_no_flow_init;
  o.flow_prior_to_field = FLAGS_flow_prior_to_field;
  o.particles.particle_pixels = FLAGS_particle_pixels;
  o.particles.max_children = FLAGS_max_particle_children;
  o.particles.max_particles = FLAGS_max_particles;
  o.profile = FLAGS_profile;
  return o;
}

}  // namespace es
