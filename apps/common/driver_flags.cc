#include "apps/common/driver_flags.h"

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

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
DEFINE_int32(ranks, 1, "Train es_static, es_flowinit and es_train on this "
             "many MPI ranks (processes), started by mpiexec, which must be "
             "on PATH; each renders its share of --batch_frames frames per "
             "iteration (es_flowinit: of each batch of flow samples). Needs "
             "a build with MPI (-DES_MPI) and --device cpu. With --scenes: "
             "the ranks of the whole batch, shared by its groups.");
DEFINE_int32(batch_frames, -1, "Frames per iteration of es_static and "
             "es_train (-1: one per rank, --ranks).");
DEFINE_bool(profile, false, "Pass --profile to es_static and es_train: "
            "each prints where its iterations' time goes, by stage and by "
            "part (render, loop texture render, fields, Euler chain, "
            "backward, Adam, densification, evaluation). OUT/timings.json "
            "has every stage's seconds in any case.");
DEFINE_string(scenes, "", "A batch of scenes instead of --scene: directories "
              "separated by commas, or a text file listing one per line. "
              "Each runs as its own eulersplat on a group of the --ranks "
              "(--groups side by side), into OUT/<its folder's name>, its "
              "log in OUT/<name>.log; its stage lines are printed prefixed "
              "with its name. A scene that fails is reported, the others "
              "go on, and the batch exits 1. Every other flag applies to "
              "each scene.");
DEFINE_int32(groups, 0, "--scenes: groups of ranks, each running one scene "
             "at a time (1 to --ranks; 0: one per scene, at most --ranks). "
             "The ranks are shared as evenly as can be.");
DEFINE_string(pose_script, "", "Run as `bash SCRIPT SCENE` instead of "
              "es_poses (COLMAP) when the scene has no sparse/0; it must "
              "write SCENE/sparse/0.");

namespace es {
namespace {

namespace fs = std::filesystem;

// -1 (the preset's value) or at least `min`.
void RequirePresetOrAtLeast(const std::string& flag, int value, int min) {
  if (value != -1) RequireAtLeast(flag, value, min);
}

// The checks of one run's flags but its scene; `largest_group`: the most
// ranks a run gets (a batch's groups share --ranks), which need MPI when
// above 1 and --batch_frames to cover them.
void CheckRunFlags(int largest_group) {
  RequireAtLeast("cycle_length", FLAGS_cycle_length, 1);
  RequirePresetOrAtLeast("static_iterations", FLAGS_static_iterations, 1);
  RequirePresetOrAtLeast("flow_iterations", FLAGS_flow_iterations, 0);
  RequirePresetOrAtLeast("joint_iterations", FLAGS_joint_iterations, 0);
  RequirePresetOrAtLeast("animate_frames", FLAGS_animate_frames, 1);
  if (FLAGS_image_scale != -1) {
    RequirePositive("image_scale", FLAGS_image_scale);
  }
  RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  if (FLAGS_batch_frames != -1) {
    RequireAtLeast("batch_frames", FLAGS_batch_frames, largest_group);
  }
  if (largest_group > 1 && !BuiltWithMpi()) {
    throw InputError("--ranks " + std::to_string(FLAGS_ranks) +
                     ": this build has no MPI (install libopenmpi-dev and "
                     "openmpi-bin, configure with -DES_MPI=ON)");
  }
  CheckPresetName(FLAGS_preset);
  std::string name;
  if (ParseDeviceFlag(FLAGS_device, &name) != ComputeDevice::kCpu) {
    if (largest_group > 1 || FLAGS_batch_frames > 1) {
      throw InputError("--ranks and --batch_frames train on the CPU only "
                       "(--device cpu)");
    }
    std::printf("[eulersplat] %s run on %s; the other stages on the CPU\n",
                DeviceStageNames().c_str(), name.c_str());
  }
}

void CheckFlags() {
  if (FLAGS_out.empty() || FLAGS_scene.empty() == FLAGS_video.empty()) {
    throw InputError("--out and one of --scene, --scenes or --video are "
                     "required");
  }
  if (FLAGS_groups != 0)
    throw InputError("--groups: only with a batch of --scenes");
  RequireAtLeast("ranks", FLAGS_ranks, 1);
  CheckRunFlags(FLAGS_ranks);
}

// The flags the user set that each scene of a batch gets too: all but
// those the batch sets per scene and gflags' own.
std::vector<std::string> PassedOnFlags() {
  static const std::set<std::string> kPerScene = {
      "scenes", "groups", "scene", "video", "out", "ranks", "threads",
      "flagfile", "fromenv", "tryfromenv", "undefok"};
  std::vector<gflags::CommandLineFlagInfo> all;
  gflags::GetAllFlags(&all);
  std::vector<std::string> flags;
  for (const gflags::CommandLineFlagInfo& f : all) {
    if (!f.is_default && !kPerScene.count(f.name))
      flags.push_back("--" + f.name + "=" + f.current_value);
  }
  return flags;
}

}  // namespace

bool SceneBatchAsked() { return !FLAGS_scenes.empty(); }

SceneBatchOptions SceneBatchOptionsFromFlags() {
  if (FLAGS_out.empty() || !FLAGS_scene.empty() || !FLAGS_video.empty())
    throw InputError("--scenes needs --out, and takes neither --scene nor "
                     "--video");
  RequireAtLeast("ranks", FLAGS_ranks, 1);
  RequireAtLeast("groups", FLAGS_groups, 0);
  SceneBatchOptions o;
  o.scenes = ParseSceneList(FLAGS_scenes);
  o.out = FLAGS_out;
  o.ranks = FLAGS_ranks;
  o.groups = FLAGS_groups;
  o = CheckSceneBatch(o);
  CheckRunFlags(GroupRanks(o.ranks, o.groups).front());
  o.threads = omp_get_max_threads();  // --threads, resolved by RunApp
  o.self = fs::read_symlink("/proc/self/exe").string();
  o.flags = PassedOnFlags();
  return o;
}

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
