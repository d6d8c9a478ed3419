#include "apps/common/driver_flags.h"

#include <cstdio>
#include <string>

#include <gflags/gflags.h>
#include <omp.h>

#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "apps/common/world.h"
#include "core/base/input_error.h"
#include "solvers/pipeline/preset.h"
#include "solvers/pipeline/stage_process.h"

namespace {

std::string DeviceHelp() {
  return "Where the stages with a CUDA path run: cpu, or cuda (the first "
         "NVIDIA GPU; needs a build with the CUDA backend, -DES_CUDA=ON or "
         "AUTO with the CUDA toolkit installed; checked before any work). "
         "Passed on as --device to " + es::DeviceStageNames() +
         "; the other stages run on the CPU, and so does the tracks video "
         "(es_animate --tracks draws positions kept on the host).";
}
const std::string kDeviceHelp = DeviceHelp();

}  // namespace

DEFINE_string(scene, "", "Scene directory: images/ (or a video), optional "
              "masks/, sparse/0/ (made with COLMAP if missing). Never "
              "written into: what it lacks is made in OUT/scene.");
DEFINE_string(video, "", "A video file (mp4, mov, ...) instead of --scene: "
              "frames are chosen (--fps, --max_frames, --max_width) and "
              "written to OUT/scene, then poses and masks are made.");
DEFINE_string(masks, "", "auto: find the water from the video (default "
              "when the scene has no masks/); none: everything is static; "
              "or a folder of masks named like the frames (white = water; "
              "with --video, named by video frame: frame_000000.png, ...).");
DEFINE_double(fps, 0, "--video: frames per second kept (0: the video's "
              "own rate).");
DEFINE_int32(max_frames, 150, "--video: at most this many frames, from "
             "the start.");
DEFINE_int32(max_width, 640, "--video: frames wider than this are scaled "
             "down (0: never).");
DEFINE_int32(mask_probe_iterations, -1, "Iterations of the static fit "
             "auto masks are found with (-1: half the preset's Stage 1).");
DEFINE_string(out, "", "Output directory (created).");
DEFINE_string(preset, "auto",
              "auto: the preset predicted to finish within 10 minutes on "
              "the CPU threads used (an hour with --device cuda), from the "
              "clip's frames and size: paper with a GPU where it fits, "
              "else quick, trained narrower than 320 px (down to 160) where "
              "a big clip needs it; a clip at most 160 px wide always gets "
              "quick as it is (solvers/pipeline/preset_choice.h prints "
              "why). quick: a few minutes on 2 cores, at most 320 px wide, "
              "small fields, 600 static + 4000 joint iterations; paper: the "
              "paper's settings (10k static + 20k joint iterations, L = 15, "
              "full-size fields).");
DEFINE_int32(static_iterations, -1, "Override the preset's Stage 1 "
             "iterations (>= 1; -1: preset).");
DEFINE_int32(flow_iterations, -1, "Override the preset's V pretraining "
             "iterations (>= 0; -1: preset).");
DEFINE_int32(joint_iterations, -1, "Override the preset's Stage 3 "
             "iterations (>= 0; -1: preset).");
DEFINE_int32(cycle_length, 15, "Loop length L in frames (at most the "
             "number of frames).");
DEFINE_double(image_scale, -1, "Override the preset's image scale (-1: "
              "preset; quick scales frames down to at most 320 px wide).");
DEFINE_int32(animate_frames, -1, "Frames of each animation (>= 1; -1: "
             "4 L).");
DEFINE_double(dynamic_threshold, 0.2, "sigmoid(dynamic_logit) above which a "
              "Gaussian is water.");
DEFINE_bool(white_background, false, "Train and render on white.");
DEFINE_string(static_dir, "", "Where Stage 1 and the flow init live (default "
              "OUT/static). Runs that name the same folder share one static "
              "model and one pretrained V, as ablations should.");
DEFINE_string(train_flags, "", "Extra flags for es_train, space-separated, "
              "e.g. \"--no_residual\" or \"--no_random_start --seed 3\" "
              "(ablations).");
DEFINE_bool(animate, true, "Render the looping videos and contact sheet "
            "(off: train and evaluate only).");
DEFINE_string(device, "cpu", kDeviceHelp.c_str());
DEFINE_int32(ranks, 1, "Train es_static and es_train on this many MPI ranks "
             "(processes), started by mpiexec, which must be on PATH; each "
             "renders its share of --batch_frames frames per iteration. "
             "Needs a build with MPI (-DES_MPI) and --device cpu.");
DEFINE_int32(batch_frames, -1, "Frames per iteration of es_static and "
             "es_train (-1: one per rank, --ranks).");
DEFINE_bool(profile, false, "Pass --profile to es_static and es_train: "
            "each prints where its iterations' time goes, by stage and by "
            "part (render, loop texture render, fields, Euler chain, "
            "backward, Adam, densification, evaluation). OUT/timings.json "
            "has every stage's seconds in any case.");
DEFINE_string(pose_script, "", "Run as `bash SCRIPT SCENE` instead of "
              "es_poses (COLMAP) when the scene has no sparse/0; it must "
              "write SCENE/sparse/0.");

namespace es {
namespace {

// -1 (the preset's value) or at least `min`.
void RequirePresetOrAtLeast(const std::string& flag, int value, int min) {
  if (value != -1) RequireAtLeast(flag, value, min);
}

void CheckFlags() {
  if (FLAGS_out.empty() || FLAGS_scene.empty() == FLAGS_video.empty()) {
    throw InputError("--out and one of --scene or --video are required");
  }
  RequireAtLeast("cycle_length", FLAGS_cycle_length, 1);
  RequirePresetOrAtLeast("static_iterations", FLAGS_static_iterations, 1);
  RequirePresetOrAtLeast("flow_iterations", FLAGS_flow_iterations, 0);
  RequirePresetOrAtLeast("joint_iterations", FLAGS_joint_iterations, 0);
  RequirePresetOrAtLeast("animate_frames", FLAGS_animate_frames, 1);
  if (FLAGS_image_scale != -1) {
    RequirePositive("image_scale", FLAGS_image_scale);
  }
  RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  RequireAtLeast("ranks", FLAGS_ranks, 1);
  if (FLAGS_batch_frames != -1) {
    RequireAtLeast("batch_frames", FLAGS_batch_frames, FLAGS_ranks);
  }
  if (FLAGS_ranks > 1 && !BuiltWithMpi()) {
    throw InputError("--ranks " + std::to_string(FLAGS_ranks) +
                     ": this build has no MPI (install libopenmpi-dev and "
                     "openmpi-bin, configure with -DES_MPI=ON)");
  }
  CheckPresetName(FLAGS_preset);
  std::string name;
  if (ParseDeviceFlag(FLAGS_device, &name) != ComputeDevice::kCpu) {
    if (FLAGS_ranks > 1 || FLAGS_batch_frames > 1) {
      throw InputError("--ranks and --batch_frames train on the CPU only "
                       "(--device cpu)");
    }
    std::printf("[eulersplat] %s run on %s; the other stages on the CPU\n",
                DeviceStageNames().c_str(), name.c_str());
  }
}

}  // namespace

PipelineOptions DriverOptionsFromFlags() {
  CheckFlags();
  PipelineOptions o;
  o.scene = FLAGS_scene;
  o.video = FLAGS_video;
  o.out = FLAGS_out;
  o.masks = FLAGS_masks;
  o.import.fps = FLAGS_fps;
  o.import.max_frames = FLAGS_max_frames;
  o.import.max_width = FLAGS_max_width;
  o.mask_probe_iterations = FLAGS_mask_probe_iterations;
  o.preset = FLAGS_preset;
  o.static_iterations = FLAGS_static_iterations;
  o.flow_iterations = FLAGS_flow_iterations;
  o.joint_iterations = FLAGS_joint_iterations;
  o.cycle_length = FLAGS_cycle_length;
  o.image_scale = FLAGS_image_scale;
  o.animate_frames = FLAGS_animate_frames;
  o.dynamic_threshold = FLAGS_dynamic_threshold;
  o.white_background = FLAGS_white_background;
  o.static_dir = FLAGS_static_dir;
  o.train_flags = FLAGS_train_flags;
  o.animate = FLAGS_animate;
  o.device = FLAGS_device;
  o.pose_script = FLAGS_pose_script;
  o.ranks = FLAGS_ranks;
  o.batch_frames = FLAGS_batch_frames;
  o.threads = omp_get_max_threads();  // --threads, resolved by RunApp
  o.profile = FLAGS_profile;
  return o;
}

}  // namespace es
