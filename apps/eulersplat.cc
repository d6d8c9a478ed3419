// The all-in-one driver: from a video (or a scene directory) to a looping
// 4D model, a looping video, metrics and a contact sheet. Runs the stage
// binaries that sit next to it (es_poses, es_masks, es_static, es_flowinit,
// es_train, es_animate, es_export, es_eval), each a process of its own so
// every stage can also be run, resumed or debugged alone with the very
// same flags the driver prints.
//
//   eulersplat --video FILE --out DIR [--preset quick|paper]
//   eulersplat --scene DIR --out DIR [--preset quick|paper]
//              [--device cpu|cuda]
//
// OUT/scene/           the frames of --video, or a view of --scene that
//                      adds what it lacks (poses, masks) without writing
//                      into it (apps/common/scene_inputs.h)
// OUT/masks_sheet.png  auto masks: the frames with their water, to check
// OUT/static/          Stage 1 (static.ply) and Stage 2 (motion_field.bin);
//                      --static_dir puts them elsewhere (shared ablations)
// OUT/model/           Stage 3, the looping model (es_train)
// OUT/animate/         looping video along the input trajectory, with tracks
// OUT/animate_fixed/   fixed-view video and its x-t slice
// OUT/web/             web page that plays the loop (es_export)
// OUT/frame_0.ply      loop frame 0 as a standard 3DGS PLY
// OUT/eval/eval.json   metrics (es_eval)
// OUT/plots/           training plots: loss by term, held-out PSNR vs wall
//                      time, Gaussians (es_plot on each history.csv)
// OUT/contact_sheet.png  frames of both videos and the main plots
//
// A stage whose outputs exist is skipped (delete its folder to redo it);
// interrupted training resumes from its checkpoint.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gflags/gflags.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/common/app_main.h"
#include "apps/common/child_process.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "apps/common/run_lock.h"
#include "apps/common/scene_inputs.h"
#include "core/io/colmap_io.h"
#include "core/io/image_file.h"
#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/model/dynamic_set.h"
#include "core/viz/video_writer.h"
#include "solvers/train/joint_trainer.h"

namespace {

// The stage binaries that take --device (apps/common/device_flag.h): the
// driver passes its own on to every run of them (RunStage); the other
// stages run on the CPU. A stage that gains a device path joins here.
const std::vector<std::string> kDeviceStages = {
    "es_static", "es_flowinit", "es_train", "es_animate", "es_eval"};

std::string DeviceStageNames() {
  std::string names;
  for (const std::string& s : kDeviceStages)
    names += (names.empty() ? "" : ", ") + s;
  return names;
}

std::string DeviceHelp() {
  return "Where the stages with a CUDA path run: cpu, or cuda (the first "
         "NVIDIA GPU; needs a build with the CUDA backend, -DES_CUDA=ON or "
         "AUTO with the CUDA toolkit installed; checked before any work). "
         "Passed on as --device to " + DeviceStageNames() +
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
DEFINE_string(preset, "quick",
              "quick: a few minutes on 2 cores, at most 320 px wide, small "
              "fields, 600 static + 4000 joint iterations; paper: the "
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
DEFINE_string(pose_script, "", "Run as `bash SCRIPT SCENE` instead of "
              "es_poses (COLMAP) when the scene has no sparse/0; it must "
              "write SCENE/sparse/0.");

namespace {

namespace fs = std::filesystem;

struct Preset {
  int static_iterations;
  int flow_iterations;
  int joint_iterations;
  int motion_resolution, residual_resolution;  // V's and D's triplanes
  int motion_channels, residual_channels;
  int motion_width, residual_width;
  int max_width;  // frames wider than this are scaled down (0: never)
  int sh_degree;
  int densify_from, densify_interval;
};

Preset MakePreset(const std::string& name) {
  if (name == "quick") {
    // 4000 joint iterations: at 600, and still at 2000, the water's PSNR
    // and texture were rising (docs/results/targets-by-round.md, the 2000-
    // and 4000-iteration rounds). D at 64^2 x 16, width 128: sharper,
    // livelier water for 11-36% more joint time
    // (docs/results/realism-2026-12-03.md, "The quick preset's residual
    // field D").
    return {600, 300, 4000, 32, 64, 8, 16, 32, 128, 320, 1, 100, 100};
  }
  if (name == "paper") {
    return {10000, 2000, 20000, 128, 128, 12, 16, 64, 128, 0, 3, 500, 100};
  }
  throw es::InputError("--preset: unknown preset '" + name +
                       "' (quick or paper)");
}

fs::path BinaryDir() {
  return fs::read_symlink("/proc/self/exe").parent_path();
}

std::string Join(const std::vector<std::string>& args) {
  std::string out;
  for (const std::string& a : args) out += (out.empty() ? "" : " ") + a;
  return out;
}

// True if `binary` takes --device (kDeviceStages) and `args` do not set
// it already (a stage that must run on the CPU says --device cpu).
bool PassDevice(const std::string& binary,
                const std::vector<std::string>& args) {
  const std::string name = fs::path(binary).filename().string();
  if (std::find(kDeviceStages.begin(), kDeviceStages.end(), name) ==
      kDeviceStages.end())
    return false;
  return std::none_of(args.begin(), args.end(), [](const std::string& a) {
    return a == "--device" || a.rfind("--device=", 0) == 0;
  });
}

// Runs a stage binary from this binary's directory (no shell: arguments go
// through untouched), with --device where it takes it. Returns its exit
// status; the stage dies with the driver.
int RunStage(const std::string& binary, std::vector<std::string> args) {
  const std::string path = binary.find('/') == std::string::npos
                               ? (BinaryDir() / binary).string()
                               : binary;
  if (PassDevice(binary, args)) {
    args.insert(args.end(), {"--device", FLAGS_device});
  }
  std::vector<std::string> all = {path};
  all.insert(all.end(), args.begin(), args.end());
  std::printf("\n$ %s\n", Join(all).c_str());
  std::fflush(stdout);
  return es::RunChildProcess(path, args);
}

void RunOrThrow(const std::string& stage, const std::string& binary,
                const std::vector<std::string>& args) {
  const int status = RunStage(binary, args);
  if (status != 0) {
    throw es::InputError(stage + " failed (" + binary + " exit status " +
                         std::to_string(status) + "; its message is above)");
  }
}

bool AllExist(const std::vector<fs::path>& paths) {
  return std::all_of(paths.begin(), paths.end(),
                     [](const fs::path& p) { return fs::exists(p); });
}

void Skip(const std::string& stage, const fs::path& where) {
  std::printf("\n[%s] skipped: outputs exist in %s (delete them to redo)\n",
              stage.c_str(), where.string().c_str());
}

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}

// The preset's image scale for this scene: quick keeps frames at most
// max_width wide.
double ImageScale(const fs::path& scene, const Preset& preset) {
  if (FLAGS_image_scale > 0) return FLAGS_image_scale;
  if (preset.max_width <= 0) return 1.0;
  const es::ColmapModel model =
      es::ReadColmapModel((scene / "sparse" / "0").string());
  int width = 0;
  for (const auto& [id, camera] : model.cameras) {
    width = std::max(width, camera.width);
  }
  return width > preset.max_width
             ? static_cast<double>(preset.max_width) / width
             : 1.0;
}

// Training plots (es_plot) that go on the contact sheet, in this order.
const char* const kSheetPlots[] = {"static_psnr.png", "joint_loss.png",
                                   "joint_psnr.png"};
// Height of a plot on the contact sheet: its text stays readable.
constexpr int kSheetPlotHeight = 400;

// Frames of the fixed-view animation over one loop and of the tracks video,
// four per row, each labelled, and below them the training plots: what the
// run produced, at a glance. The frames are enlarged to the plots' width.
void WriteContactSheet(const fs::path& out, int cycle_length) {
  std::vector<std::pair<cv::Mat, std::string>> tiles;
  const auto add = [&](const fs::path& dir, const std::string& label) {
    for (int k = 0; k < 4; ++k) {
      const int frame = k * cycle_length / 4;
      cv::Mat image = cv::imread(
          (dir / es::AnimationFrameName(frame)).string(), cv::IMREAD_COLOR);
      if (!image.empty()) {
        tiles.emplace_back(image, label + " t=" + std::to_string(frame));
      }
    }
  };
  add(out / "animate_fixed" / "frames", "fixed view");
  add(out / "animate" / "tracks", "tracks");
  std::vector<cv::Mat> plots;
  int plots_width = 0;
  for (const char* name : kSheetPlots) {
    cv::Mat plot = cv::imread((out / "plots" / name).string(),
                              cv::IMREAD_COLOR);
    if (plot.empty()) continue;
    cv::resize(plot, plot,
               {plot.cols * kSheetPlotHeight / plot.rows, kSheetPlotHeight},
               0, 0, cv::INTER_AREA);
    plots_width += plot.cols;
    plots.push_back(plot);
  }
  if (tiles.empty() && plots.empty()) return;
  const int columns = 4;
  cv::Size size(0, 0);
  if (!tiles.empty()) {
    size = tiles[0].first.size();
    const double grow = std::max(
        1.0, static_cast<double>(plots_width) / (columns * size.width));
    size = cv::Size(static_cast<int>(size.width * grow),
                    static_cast<int>(size.height * grow));
  }
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const int width = std::max(columns * size.width, plots_width);
  const int plots_height = plots.empty() ? 0 : kSheetPlotHeight;
  cv::Mat sheet(rows * size.height + plots_height, width, CV_8UC3,
                cv::Scalar(40, 40, 40));
  for (size_t i = 0; i < tiles.size(); ++i) {
    cv::Mat tile = tiles[i].first;
    if (tile.size() != size) cv::resize(tile, tile, size);
    const cv::Rect where((i % columns) * size.width,
                         (i / columns) * size.height, size.width,
                         size.height);
    tile.copyTo(sheet(where));
    const double font = std::max(0.4, size.width / 640.0);
    cv::putText(sheet, tiles[i].second,
                where.tl() + cv::Point(6, static_cast<int>(20 * font / 0.5)),
                cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(255, 255, 255), 1,
                cv::LINE_AA);
  }
  int x = 0;
  for (const cv::Mat& plot : plots) {
    plot.copyTo(sheet(cv::Rect(x, rows * size.height, plot.cols, plot.rows)));
    x += plot.cols;
  }
  es::WriteImageAtomically((out / "contact_sheet.png").string(), sheet);
}

// Numbers the driver's stages "k/N" and says how long the run has taken,
// so a person sees where a long run stands.
class StageLog {
 public:
  explicit StageLog(int total)
      : total_(total), start_(std::chrono::steady_clock::now()) {}

  void Begin(const std::string& name) {
    const double seconds = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start_)
                               .count();
    std::printf("\n[eulersplat] stage %d/%d: %s (%.0f s so far)\n", ++done_,
                total_, name.c_str(), seconds);
    std::fflush(stdout);
  }

 private:
  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
};

// Iterations between progress lines / held-out evaluations of a stage of
// `iterations`: about 20 history rows and 5 evaluations per run.
std::string LogEvery(int iterations) {
  return std::to_string(std::clamp(iterations / 20, 1, 100));
}
std::string EvalEvery(int iterations) {
  return std::to_string(std::max(1, iterations / 5));
}

// What every stage of one run shares.
struct Pipeline {
  StageLog* stages = nullptr;
  Preset preset;
  fs::path scene, out, static_folder;
  bool has_masks = false;
  es::ComputeDevice device = es::ComputeDevice::kCpu;
  std::vector<std::string> common;      // --scene, --image_scale
  std::vector<std::string> background;  // --white_background or nothing

  fs::path static_dir() const { return static_folder; }
  fs::path static_ply() const { return static_dir() / "static.ply"; }
  fs::path model_dir() const { return out / "model"; }
  fs::path eval_dir() const { return out / "eval"; }

  // common + extra (+ background if `render`).
  std::vector<std::string> Args(const std::vector<std::string>& extra,
                                bool render) const {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    if (render) args.insert(args.end(), background.begin(), background.end());
    return args;
  }
};

// Checkpoints at least six times per stage (at most every 1000
// iterations), so a killed quick run loses a sixth of a stage, not all.
int CheckpointInterval(int iterations) {
  return std::clamp(iterations / 6, 1, 1000);
}

// Stage 1's flags but --out and --iterations (shared with the mask probe).
std::vector<std::string> StaticFlags(const Pipeline& run) {
  const Preset& p = run.preset;
  const int sh_interval =
      std::max(1, p.static_iterations / (p.sh_degree + 1));
  return run.Args(
      {"--sh_degree", std::to_string(p.sh_degree), "--sh_degree_interval",
       std::to_string(sh_interval), "--densify_from",
       std::to_string(p.densify_from), "--densify_interval",
       std::to_string(p.densify_interval), "--dynamic_threshold",
       Number(FLAGS_dynamic_threshold), "--checkpoint_every",
       std::to_string(CheckpointInterval(p.static_iterations)), "--log_every",
       LogEvery(p.static_iterations), "--eval_every",
       EvalEvery(p.static_iterations)},
      true);
}

void StaticStage(const Pipeline& run) {
  run.stages->Begin("static model (es_static)");
  if (AllExist({run.static_ply(), run.static_dir() / "metrics.json"})) {
    Skip("static", run.static_dir());
    return;
  }
  std::vector<std::string> args = {
      "--out", run.static_dir().string(), "--iterations",
      std::to_string(run.preset.static_iterations)};
  const std::vector<std::string> flags = StaticFlags(run);
  args.insert(args.end(), flags.begin(), flags.end());
  if (!run.has_masks) args.insert(args.end(), {"--mask_weight", "0"});
  // es_static resumes only from a checkpoint that exists.
  if (fs::exists(run.static_dir() / "checkpoint.bin")) {
    args.push_back("--resume");
  }
  RunOrThrow("[static]", "es_static", args);
}

// V from optical flow. A failure is not fatal: Stage 3 then learns V from
// scratch.
void FlowStage(const Pipeline& run) {
  run.stages->Begin("motion field from optical flow (es_flowinit)");
  if (AllExist({run.static_dir() / "motion_field.bin",
                run.static_dir() / "flow_metrics.json"})) {
    Skip("flow init", run.static_dir());
    return;
  }
  const Preset& p = run.preset;
  const std::vector<std::string> args = run.Args(
      {"--static", run.static_ply().string(), "--out",
       run.static_dir().string(), "--iterations",
       std::to_string(p.flow_iterations), "--triplane_res",
       std::to_string(p.motion_resolution), "--triplane_channels",
       std::to_string(p.motion_channels), "--mlp_width",
       std::to_string(p.motion_width), "--dynamic_threshold",
       Number(FLAGS_dynamic_threshold), "--log_every",
       LogEvery(p.flow_iterations)},
      true);
  if (RunStage("es_flowinit", args) != 0) {
    std::printf("[flow init] failed (see above): joint training learns V "
                "from scratch\n");
  }
}

void JointStage(const Pipeline& run) {
  run.stages->Begin("joint training of the loop (es_train)");
  if (AllExist({run.model_dir() / "loop.txt",
                run.model_dir() / "metrics.json"})) {
    Skip("joint", run.model_dir());
    return;
  }
  const Preset& p = run.preset;
  std::vector<std::string> args = run.Args(
      {"--init", run.static_dir().string(), "--out",
       run.model_dir().string(), "--iterations",
       std::to_string(p.joint_iterations), "--cycle_length",
       std::to_string(FLAGS_cycle_length), "--resume", "--dynamic_threshold",
       Number(FLAGS_dynamic_threshold), "--motion_resolution",
       std::to_string(p.motion_resolution), "--motion_channels",
       std::to_string(p.motion_channels), "--motion_width",
       std::to_string(p.motion_width), "--residual_resolution",
       std::to_string(p.residual_resolution), "--residual_channels",
       std::to_string(p.residual_channels), "--residual_width",
       std::to_string(p.residual_width), "--checkpoint_interval",
       std::to_string(CheckpointInterval(p.joint_iterations)),
       "--log_interval", LogEvery(p.joint_iterations), "--eval_interval",
       EvalEvery(p.joint_iterations)},
      true);
  if (!run.has_masks) args.insert(args.end(), {"--mask_weight", "0"});
  // Later flags win in gflags, so --train_flags can override the preset's.
  std::istringstream extra(FLAGS_train_flags);
  for (std::string flag; extra >> flag;) args.push_back(flag);
  RunOrThrow("[joint]", "es_train", args);
}

// Two animations: along the input trajectory with tracks, and a fixed
// view with its x-t slice.
void AnimateStage(const Pipeline& run) {
  const int frames = FLAGS_animate_frames > 0 ? FLAGS_animate_frames
                                              : 4 * FLAGS_cycle_length;
  struct Video {
    std::string name;
    std::string last_output;  // written last: its presence means done
    std::vector<std::string> flags;
    bool tracks;
  };
  for (const Video& v :
       {Video{"animate", "tracks.mp4", {"--camera", "input", "--tracks"},
              true},
        Video{"animate_fixed", "xt_slice.png",
              {"--camera", "fixed", "--xt_slice", "auto"}, false}}) {
    const fs::path dir = run.out / v.name;
    run.stages->Begin(v.name + " video (es_animate)");
    if (AllExist({dir / "animation.mp4", dir / v.last_output})) {
      Skip(v.name, dir);
      continue;
    }
    std::vector<std::string> args =
        run.Args({"--model", run.model_dir().string(), "--frames",
                  std::to_string(frames), "--out", dir.string()},
                 true);
    args.insert(args.end(), v.flags.begin(), v.flags.end());
    if (v.tracks && run.device != es::ComputeDevice::kCpu) {
      std::printf("[%s] rendered on the CPU: es_animate --tracks draws the "
                  "Gaussians' positions, which the GPU keeps\n",
                  v.name.c_str());
      args.insert(args.end(), {"--device", "cpu"});
    }
    RunOrThrow("[" + v.name + "]", "es_animate", args);
  }
}

// A web page that plays the loop with orbit controls, and a PLY of loop
// frame 0 for other 3DGS tools. Not fatal: the page needs the npm packages
// scripts/setup.sh installs.
void ExportStage(const Pipeline& run) {
  run.stages->Begin("web page and frame PLY (es_export)");
  const fs::path dir = run.out / "web", ply = run.out / "frame_0.ply";
  if (AllExist({dir / "view.json", ply})) {
    Skip("export", dir);
    return;
  }
  if (RunStage("es_export",
               run.Args({"--model", run.model_dir().string(), "--web",
                         dir.string(), "--ply", ply.string()},
                        true)) != 0) {
    std::printf("[export] failed (its message is above); the other outputs "
                "are complete\n");
  }
}

void EvalStage(const Pipeline& run) {
  run.stages->Begin("evaluation (es_eval)");
  if (AllExist({run.eval_dir() / "eval.json"})) {
    Skip("eval", run.eval_dir());
    return;
  }
  std::vector<std::string> args = {"--model", run.model_dir().string(),
                                   "--out", run.eval_dir().string()};
  // Stage 2's V at the same water Gaussians: did joint training improve it?
  const fs::path flow_init = run.static_dir() / "motion_field.bin";
  if (fs::exists(flow_init)) {
    args.insert(args.end(), {"--reference_motion", flow_init.string()});
  }
  RunOrThrow("[eval]", "es_eval", run.Args(args, true));
}

// The training histories as PNGs in OUT/plots (es_plot), redrawn on every
// run (cheap). A failure only costs the plots.
void PlotStage(const Pipeline& run) {
  run.stages->Begin("training plots (es_plot)");
  const fs::path plots = run.out / "plots";
  for (const auto& [history, prefix] :
       {std::pair{run.static_dir() / "history.csv", "static_"},
        std::pair{run.static_dir() / "flow_history.csv", "flow_"},
        std::pair{run.model_dir() / "history.csv", "joint_"}}) {
    if (!fs::exists(history)) continue;
    if (RunStage("es_plot", {"--history", history.string(), "--out",
                             plots.string(), "--prefix", prefix}) != 0) {
      std::printf("[plots] es_plot failed on %s (see above)\n",
                  history.string().c_str());
    }
  }
}

// Stops the run after Stage 1 (returning false) when nothing is water.
bool HasDynamicGaussians(const Pipeline& run) {
  const int num_dynamic = static_cast<int>(
      es::DynamicSet(es::ReadPly(run.static_ply().string()),
                     FLAGS_dynamic_threshold)
          .size());
  if (num_dynamic > 0) {
    std::printf("\n[eulersplat] the static model marks %d Gaussians "
                "dynamic\n", num_dynamic);
    return true;
  }
  std::printf(
      "\n[eulersplat] the static model marks no Gaussian dynamic "
      "(sigmoid(dynamic_logit) > %g), so there is no motion field, loop "
      "or animation to make: stopping after the static model, %s\n",
      FLAGS_dynamic_threshold, run.static_ply().string().c_str());
  if (!run.has_masks) {
    std::printf("[eulersplat] the scene has no masks/: without them "
                "Stage 1 has no mask (BCE) term and marks no Gaussian as "
                "water. Add masks/ (same file names, white = water) to "
                "animate it.\n");
  }
  return false;
}

es::InputRequest MakeInputRequest() {
  es::InputRequest r;
  r.video = FLAGS_video;
  r.scene = FLAGS_scene;
  r.out = FLAGS_out;
  r.masks = FLAGS_masks;
  r.import.fps = FLAGS_fps;
  r.import.max_frames = FLAGS_max_frames;
  r.import.max_width = FLAGS_max_width;
  r.pose_script = FLAGS_pose_script;
  return r;
}

es::MaskProbe MakeMaskProbe(const Pipeline& run) {
  es::MaskProbe probe;
  probe.iterations = FLAGS_mask_probe_iterations >= 0
                         ? FLAGS_mask_probe_iterations
                         : std::max(1, run.preset.static_iterations / 2);
  probe.static_flags = StaticFlags(run);
  probe.mask_flags = run.Args({}, true);
  return probe;
}

// -1 (the preset's value) or at least `min`.
void RequirePresetOrAtLeast(const std::string& flag, int value, int min) {
  if (value != -1) es::RequireAtLeast(flag, value, min);
}

// Returns the device the stages in kDeviceStages run on, saying so.
es::ComputeDevice CheckFlags() {
  if (FLAGS_out.empty() || FLAGS_scene.empty() == FLAGS_video.empty()) {
    throw es::InputError("--out and one of --scene or --video are required");
  }
  es::RequireAtLeast("cycle_length", FLAGS_cycle_length, 1);
  RequirePresetOrAtLeast("static_iterations", FLAGS_static_iterations, 1);
  RequirePresetOrAtLeast("flow_iterations", FLAGS_flow_iterations, 0);
  RequirePresetOrAtLeast("joint_iterations", FLAGS_joint_iterations, 0);
  RequirePresetOrAtLeast("animate_frames", FLAGS_animate_frames, 1);
  if (FLAGS_image_scale != -1) {
    es::RequirePositive("image_scale", FLAGS_image_scale);
  }
  es::RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  std::string name;
  const es::ComputeDevice device = es::ParseDeviceFlag(FLAGS_device, &name);
  if (device != es::ComputeDevice::kCpu) {
    std::printf("[eulersplat] %s run on %s; the other stages on the CPU\n",
                DeviceStageNames().c_str(), name.c_str());
  }
  return device;
}

int Main() {
  Pipeline run;
  run.device = CheckFlags();
  run.preset = MakePreset(FLAGS_preset);
  Preset& p = run.preset;
  if (FLAGS_static_iterations >= 0) {
    p.static_iterations = FLAGS_static_iterations;
  }
  if (FLAGS_flow_iterations >= 0) p.flow_iterations = FLAGS_flow_iterations;
  if (FLAGS_joint_iterations >= 0) {
    p.joint_iterations = FLAGS_joint_iterations;
  }
  run.out = FLAGS_out;
  run.static_folder = FLAGS_static_dir.empty() ? run.out / "static"
                                               : fs::path(FLAGS_static_dir);
  const auto start = std::chrono::steady_clock::now();
  es::PrepareOutputDirectory(FLAGS_out, "out");
  // One run per output folder; runs sharing a --static_dir take turns on
  // it until its Stages 1 and 2 are written.
  const es::RunLock out_lock(run.out.string(),
                             es::RunLock::Mode::kFailIfHeld);
  std::optional<es::RunLock> static_lock;
  if (!FLAGS_static_dir.empty()) {
    static_lock.emplace(run.static_folder.string(),
                        es::RunLock::Mode::kWaitIfHeld);
  }
  const es::InputRequest request = MakeInputRequest();
  run.scene = es::PrepareFramesAndPoses(request, RunOrThrow);
  const double scale = ImageScale(run.scene, p);
  const int num_frames = static_cast<int>(
      es::ReadColmapModel((run.scene / "sparse" / "0").string())
          .images.size());
  // Checked here, not in Stage 3: a loop longer than the video would fail
  // only after Stage 1 had trained.
  es::RequireAtMost("cycle_length", FLAGS_cycle_length, num_frames,
                    run.scene.string() + " has " +
                        std::to_string(num_frames) + " frames");
  run.common = {"--scene", run.scene.string(), "--image_scale",
                Number(scale)};
  if (FLAGS_white_background) run.background = {"--white_background"};
  const es::PreparedScene prepared =
      es::PrepareMasks(request, run.scene, MakeMaskProbe(run), RunOrThrow);
  run.has_masks = prepared.has_masks;
  // static, flow, joint, export, eval, plots (+ two videos, contact sheet).
  StageLog stages(prepared.static_only ? 1 : 6 + (FLAGS_animate ? 3 : 0));
  run.stages = &stages;
  std::printf("\n[eulersplat] preset %s: %d static / %d flow / %d joint "
              "iterations, L = %d, image scale %.3g, masks %s\n",
              FLAGS_preset.c_str(), p.static_iterations, p.flow_iterations,
              p.joint_iterations, FLAGS_cycle_length, scale,
              run.has_masks ? "yes" : "no");

  if (prepared.static_only) {
    std::printf("[eulersplat] %s: training the static model only (no "
                "motion field, loop or animation)\n",
                prepared.why_static.c_str());
    StaticStage(run);
    std::printf("\n[eulersplat] done: static model %s\n",
                run.static_ply().c_str());
    return 0;
  }
  StaticStage(run);
  if (!HasDynamicGaussians(run)) return 0;
  FlowStage(run);
  // Stages 1 and 2 are on disk and the later stages only read them: other
  // runs sharing the --static_dir (ablations, seeds) may go on alongside.
  static_lock.reset();
  JointStage(run);
  if (FLAGS_animate) AnimateStage(run);
  ExportStage(run);
  EvalStage(run);
  PlotStage(run);
  if (FLAGS_animate) {
    stages.Begin("contact sheet");
    WriteContactSheet(run.out, FLAGS_cycle_length);
  }

  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  std::printf("\n[eulersplat] done in %.0f s\n  metrics        %s\n"
              "  plots          %s\n",
              seconds, (run.eval_dir() / "eval.json").c_str(),
              (run.out / "plots").c_str());
  if (FLAGS_animate) {
    std::printf("  looping video  %s\n  fixed view     %s\n"
                "  contact sheet  %s\n",
                (run.out / "animate" / "animation.mp4").c_str(),
                (run.out / "animate_fixed" / "animation.mp4").c_str(),
                (run.out / "contact_sheet.png").c_str());
  }
  if (fs::exists(run.out / "web" / "view.json")) {
    std::printf("  web page       %s (python3 -m http.server --directory "
                "%s, then open localhost:8000)\n",
                (run.out / "web" / "index.html").c_str(),
                (run.out / "web").c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Runs every stage: video -> poses -> masks -> static -> "
                    "flow init -> joint -> animate -> export -> eval -> "
                    "plots.\n"
                    "  eulersplat --video FILE --out DIR [--preset "
                    "quick|paper] [--device cpu|cuda]\n"
                    "  eulersplat --scene DIR --out DIR [--preset "
                    "quick|paper] [--device cpu|cuda]\n"
                    "Writes OUT/static, OUT/model, OUT/animate, "
                    "OUT/animate_fixed, OUT/eval, OUT/plots and "
                    "OUT/contact_sheet.png; a stage whose outputs exist is "
                    "skipped.",
                    Main);
}
