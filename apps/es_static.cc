// Stage 1: static 3DGS reconstruction with a learned per-Gaussian dynamic
// (water) probability.
//
//   es_static --scene DIR --out DIR [--iterations 10000] [--resume]
//             [--image_scale 1] [--device cpu|cuda] ...
//
// Writes DIR/static.ply (3DGS layout + dynamic_logit), DIR/metrics.json,
// DIR/history.csv (es_plot draws it) and DIR/checkpoint.bin every
// --checkpoint_every iterations.

#include <gflags/gflags.h>

#include <cstdio>
#include <string>

#include "apps/common/device_flag.h"
#include "apps/common/world.h"
#include "apps/common/flag_checks.h"
#include "apps/common/splat_rate_flags.h"
#include "solvers/train/static_stage.h"

constexpr char kUsage[] =
    "Stage 1: static reconstruction.\n"
    "  es_static --scene DIR --out DIR [--iterations N] [--resume]\n"
    "            [--device cpu|cuda] [--batch_frames B]\n"
    "Writes OUT/static.ply, OUT/metrics.json, OUT/history.csv and "
    "OUT/checkpoint.bin.";

DEFINE_string(scene, "", "Scene directory (images/, masks/, sparse/0/).");
DEFINE_string(out, "", "Output directory (created).");
DEFINE_int32(iterations, 10000, "Training iterations.");
DEFINE_bool(resume, false, "Continue from OUT/checkpoint.bin.");
DEFINE_int32(checkpoint_every, 1000,
             "Write OUT/checkpoint.bin every this many iterations (0: "
             "never).");
DEFINE_int32(log_every, 100,
             "Print progress and add a row to OUT/history.csv every this "
             "many iterations (0: neither).");
DEFINE_int32(eval_every, 1000,
             "Measure held-out PSNR into OUT/history.csv every this many "
             "iterations (and at the end; 0: only at the end).");
DEFINE_double(image_scale, 1.0, "Resize frames (and intrinsics) by this.");
DEFINE_uint64(seed, 0, "Seed for frame sampling and splitting.");
DEFINE_int32(sh_degree, 3, "Maximum SH degree (0..3).");
DEFINE_int32(sh_degree_interval, 1000,
             "Raise the SH degree by one every this many iterations.");
DEFINE_double(lr_position, 1.6e-4,
              "Initial position learning rate (times the scene extent).");
DEFINE_double(lr_position_final, 1.6e-6,
              "Final position learning rate (times the scene extent); "
              "log-linear decay over --iterations.");
DEFINE_double(lr_scale, 5e-3, "Log-scale learning rate.");
DEFINE_double(lr_rotation, 1e-3, "Quaternion learning rate.");
DEFINE_double(lr_opacity, 0.05, "Opacity-logit learning rate.");
DEFINE_double(lr_sh_dc, 2.5e-3, "SH DC learning rate.");
DEFINE_double(lr_sh_rest, 2.5e-3 / 20, "Higher-band SH learning rate.");
DEFINE_double(lr_dynamic, 0.05, "Dynamic-logit learning rate.");
DEFINE_double(ssim_weight, 0.2, "Photometric loss: (1-w) L1 + w (1-SSIM).");
DEFINE_double(mask_weight, 0.5,
              "Weight of the mask BCE on the dynamic channel (0: off).");
DEFINE_double(dynamic_threshold, 0.2,
              "Dynamic probability above which a Gaussian counts as water.");
DEFINE_bool(densify, true, "Adaptive density control (clone/split/prune).");
DEFINE_int32(densify_from, 500, "First densification iteration.");
DEFINE_int32(densify_until, 15000,
             "Last densification iteration; densification also stops at "
             "half of --iterations (3DGS: 15k of 30k) so the run ends on a "
             "settled model.");
DEFINE_int32(densify_interval, 100, "Densify every this many iterations.");
DEFINE_int32(opacity_reset_interval, 3000,
             "Reset opacities every this many iterations (0: never).");
DEFINE_double(densify_grad_threshold, 2e-4,
              "Mean view-space gradient norm that triggers clone/split.");
DEFINE_double(percent_dense, 0.01,
              "Clone below, split above this fraction of the scene extent.");
DEFINE_double(min_opacity, 0.005, "Prune Gaussians below this opacity.");
DEFINE_double(max_screen_radius, 20,
              "After the first opacity reset, prune Gaussians whose screen "
              "radius exceeded this many pixels since the last "
              "densification (3DGS: 20).");
DEFINE_double(max_world_scale, 0,
              "After the first opacity reset, prune Gaussians larger than "
              "this times the cameras' extent (3DGS: 0.1; 0: off, the "
              "default, since a hand-held video's small extent made it "
              "prune the backdrop).");
DEFINE_int32(max_gaussians, 1000000, "Cap on the number of Gaussians.");
DEFINE_bool(white_background, false, "Render on white instead of black.");
DEFINE_string(device, "cpu", es::kDeviceFlagHelp);
DEFINE_int32(batch_frames, 1, es::kBatchFramesHelp);
DEFINE_bool(profile, false,
            "Print where the training iterations' wall time goes, per stage "
            "(projection, binning, tiles, losses, Adam, densification), "
            "after the last iteration.");

int main(int argc, char** argv) {
  return es::RunAppOnRanks(argc, argv, kUsage, [](es::Communicator* comm) {
    es::RequirePositive("image_scale", FLAGS_image_scale);
    std::string device_name;
    const es::ComputeDevice device =
        es::ParseDeviceFlag(FLAGS_device, &device_name);
    es::StaticStageOptions o;
    o.scene_dir = FLAGS_scene;
    o.out_dir = FLAGS_out;
    o.scene.image_scale = FLAGS_image_scale;
    o.resume = FLAGS_resume;
    o.checkpoint_every = FLAGS_checkpoint_every;
    o.log_every = FLAGS_log_every;
    o.eval_every = FLAGS_eval_every;
    o.dynamic_threshold = FLAGS_dynamic_threshold;
    o.profile = FLAGS_profile;
    es::StaticTrainerOptions& t = o.trainer;
    t.iterations = FLAGS_iterations;
    t.seed = FLAGS_seed;
    t.max_sh_degree = FLAGS_sh_degree;
    t.sh_degree_interval = FLAGS_sh_degree_interval;
    t.splat_lr = es::SplatRatesFromFlags(
        {"lr_position", "lr_position_final", "lr_scale", "lr_rotation"});
    t.ssim_weight = FLAGS_ssim_weight;
    t.mask_weight = FLAGS_mask_weight;
    t.densify = FLAGS_densify;
    t.densify_options.from_iteration = FLAGS_densify_from;
    t.densify_options.until_iteration = FLAGS_densify_until;
    t.densify_options.interval = FLAGS_densify_interval;
    t.densify_options.opacity_reset_interval = FLAGS_opacity_reset_interval;
    t.densify_options.grad_threshold = FLAGS_densify_grad_threshold;
    t.densify_options.percent_dense = FLAGS_percent_dense;
    t.densify_options.min_opacity = FLAGS_min_opacity;
    t.densify_options.max_screen_radius = FLAGS_max_screen_radius;
    t.densify_options.max_world_scale = FLAGS_max_world_scale;
    t.densify_options.max_gaussians = FLAGS_max_gaussians;
    if (FLAGS_white_background) t.background.setOnes();
    if (device == es::ComputeDevice::kCuda)
      std::printf("training on %s\n", device_name.c_str());
    t.batch_frames = FLAGS_batch_frames;
    t.comm = comm;
    es::CheckBatchFramesFlag(t.batch_frames, *t.comm,
                             device == es::ComputeDevice::kCuda);
    es::RunStaticStage(o, es::StaticTrainerOn(device));
    return 0;
  });
}
