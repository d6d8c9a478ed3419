#include "solvers/pipeline/stage_plan.h"

#include <algorithm>
#include <sstream>

#include "core/base/number_text.h"

namespace es {
namespace {

namespace fs = std::filesystem;

// Checkpoints at least six times per stage (at most every 1000
// iterations), so a killed quick run loses a sixth of a stage, not all.
std::string CheckpointInterval(int iterations) {
  return std::to_string(std::clamp(iterations / 6, 1, 1000));
}

// Iterations between progress lines / held-out evaluations of a stage of
// `iterations`: about 20 history rows and 5 evaluations per run.
std::string LogEvery(int iterations) {
  return std::to_string(std::clamp(iterations / 20, 1, 100));
}
std::string EvalEvery(int iterations) {
  return std::to_string(std::max(1, iterations / 5));
}

void Append(std::vector<std::string>* args,
            const std::vector<std::string>& more) {
  args->insert(args->end(), more.begin(), more.end());
}

StageStep Step(const std::string& title, const std::string& label,
               const fs::path& where, const std::vector<fs::path>& outputs,
               const std::string& binary) {
  StageStep s;
  s.title = title;
  s.label = label;
  s.where = where;
  s.outputs = outputs;
  s.binary = binary;
  return s;
}

}  // namespace

bool StepIsDone(const StageStep& step) {
  return std::all_of(step.outputs.begin(), step.outputs.end(),
                     [](const fs::path& p) { return fs::exists(p); });
}

StagePlan::StagePlan(const PipelineOptions& options)
    : options_(options),
      preset_(PresetFor(options)),
      out_(options.out),
      static_dir_(options.static_dir.empty() ? out_ / "static"
                                             : fs::path(options.static_dir)) {
  if (options.white_background) background_ = {"--white_background"};
}

void StagePlan::SetScene(const fs::path& scene, double image_scale) {
  common_ = {"--scene", scene.string(), "--image_scale",
             ShortNumber(image_scale)};
}

std::vector<std::string> StagePlan::Args(const std::vector<std::string>& extra,
                                         bool render) const {
  std::vector<std::string> args = common_;
  Append(&args, extra);
  if (render) Append(&args, background_);
  return args;
}

std::vector<std::string> StagePlan::StaticFlags() const {
  const Preset& p = preset_;
  const int sh_interval = std::max(1, p.static_iterations / (p.sh_degree + 1));
  return Args({"--sh_degree", std::to_string(p.sh_degree),
               "--sh_degree_interval", std::to_string(sh_interval),
               "--densify_from", std::to_string(p.densify_from),
               "--densify_interval", std::to_string(p.densify_interval),
               "--dynamic_threshold", ShortNumber(options_.dynamic_threshold),
               "--checkpoint_every", CheckpointInterval(p.static_iterations),
               "--log_every", LogEvery(p.static_iterations), "--eval_every",
               EvalEvery(p.static_iterations)},
              true);
}

MaskProbe StagePlan::MaskProbeSettings() const {
  MaskProbe probe;
  probe.iterations = options_.mask_probe_iterations >= 0
                         ? options_.mask_probe_iterations
                         : std::max(1, preset_.static_iterations / 2);
  probe.static_flags = StaticFlags();
  probe.mask_flags = Args({}, true);
  return probe;
}

StageStep StagePlan::StaticStep() const {
  StageStep s = Step("static model (es_static)", "static", static_dir_,
                     {static_ply(), static_dir_ / "metrics.json"}, "es_static");
  s.args = {"--out", static_dir_.string(), "--iterations",
            std::to_string(preset_.static_iterations)};
  Append(&s.args, StaticFlags());
  if (!has_masks_) Append(&s.args, {"--mask_weight", "0"});
  if (options_.profile) s.args.push_back("--profile");
  // es_static resumes only from a checkpoint that exists.
  if (fs::exists(static_dir_ / "checkpoint.bin")) s.args.push_back("--resume");
  return s;
}

// A failure is not fatal: Stage 3 then learns V from scratch.
StageStep StagePlan::FlowStep() const {
  const Preset& p = preset_;
  StageStep s = Step(
      "motion field from optical flow (es_flowinit)", "flow init", static_dir_,
      {static_dir_ / "motion_field.bin", static_dir_ / "flow_metrics.json"},
      "es_flowinit");
  s.args =
      Args({"--static", static_ply().string(), "--out", static_dir_.string(),
            "--iterations", std::to_string(p.flow_iterations), "--triplane_res",
            std::to_string(p.motion_resolution), "--triplane_channels",
            std::to_string(p.motion_channels), "--mlp_width",
            std::to_string(p.motion_width), "--dynamic_threshold",
            ShortNumber(options_.dynamic_threshold), "--log_every",
            LogEvery(p.flow_iterations)},
           true);
  s.on_failure = "[flow init] failed (see above): joint training learns V "
                 "from scratch\n";
  return s;
}

StageStep StagePlan::JointStep() const {
  const Preset& p = preset_;
  StageStep s = Step(
      "joint training of the loop (es_train)", "joint", model_dir(),
      {model_dir() / "loop.txt", model_dir() / "metrics.json"}, "es_train");
  s.args = Args(
      {"--init", static_dir_.string(), "--out", model_dir().string(),
       "--iterations", std::to_string(p.joint_iterations), "--cycle_length",
       std::to_string(options_.cycle_length), "--resume",
       "--dynamic_threshold", ShortNumber(options_.dynamic_threshold),
       "--motion_resolution", std::to_string(p.motion_resolution),
       "--motion_channels", std::to_string(p.motion_channels),
       "--motion_width", std::to_string(p.motion_width),
       "--residual_resolution", std::to_string(p.residual_resolution),
       "--residual_channels", std::to_string(p.residual_channels),
       "--residual_width", std::to_string(p.residual_width),
       "--checkpoint_interval", CheckpointInterval(p.joint_iterations),
       "--log_interval", LogEvery(p.joint_iterations), "--eval_interval",
       EvalEvery(p.joint_iterations)},
      true);
  if (!has_masks_) Append(&s.args, {"--mask_weight", "0"});
  if (options_.profile) s.args.push_back("--profile");
  // Later flags win in gflags, so --train_flags can override the preset's.
  std::istringstream extra(options_.train_flags);
  for (std::string flag; extra >> flag;) s.args.push_back(flag);
  return s;
}

std::vector<StageStep> StagePlan::AnimateSteps() const {
  const int frames = options_.animate_frames > 0 ? options_.animate_frames
                                                 : 4 * options_.cycle_length;
  struct Video {
    std::string name;
    std::string last_output;  // written last: its presence means done
    std::vector<std::string> flags;
    bool tracks;
  };
  std::vector<StageStep> steps;
  for (const Video& v :
       {Video{"animate", "tracks.mp4", {"--camera", "input", "--tracks"},
              true},
        Video{"animate_fixed", "xt_slice.png",
              {"--camera", "fixed", "--xt_slice", "auto"}, false}}) {
    const fs::path dir = out_ / v.name;
    StageStep s =
        Step(v.name + " video (es_animate)", v.name, dir,
             {dir / "animation.mp4", dir / v.last_output}, "es_animate");
    s.args = Args({"--model", model_dir().string(), "--frames",
                   std::to_string(frames), "--out", dir.string()},
                  true);
    Append(&s.args, v.flags);
    if (v.tracks && options_.device != "cpu") {
      s.note = "[" + v.name + "] rendered on the CPU: es_animate --tracks "
               "draws the Gaussians' positions, which the GPU keeps\n";
      Append(&s.args, {"--device", "cpu"});
    }
    steps.push_back(s);
  }
  return steps;
}

// Not fatal: the page needs the npm packages scripts/setup.sh installs.
StageStep StagePlan::ExportStep() const {
  const fs::path dir = out_ / "web", ply = out_ / "frame_0.ply";
  StageStep s = Step("web page and frame PLY (es_export)", "export", dir,
                     {dir / "view.json", ply}, "es_export");
  s.args = Args({"--model", model_dir().string(), "--web", dir.string(),
                 "--ply", ply.string()},
                true);
  s.on_failure = "[export] failed (its message is above); the other outputs "
                 "are complete\n";
  return s;
}

StageStep StagePlan::EvalStep() const {
  StageStep s = Step("evaluation (es_eval)", "eval", eval_dir(),
                     {eval_dir() / "eval.json"}, "es_eval");
  std::vector<std::string> args = {"--model", model_dir().string(), "--out",
                                   eval_dir().string()};
  // Stage 2's V at the same water Gaussians: did joint training improve it?
  const fs::path flow_init = static_dir_ / "motion_field.bin";
  if (fs::exists(flow_init)) {
    Append(&args, {"--reference_motion", flow_init.string()});
  }
  s.args = Args(args, true);
  return s;
}

std::vector<std::pair<fs::path, std::vector<std::string>>>
StagePlan::PlotRuns() const {
  const fs::path plots = out_ / "plots";
  std::vector<std::pair<fs::path, std::vector<std::string>>> runs;
  for (const auto& [history, prefix] :
       {std::pair{static_dir_ / "history.csv", "static_"},
        std::pair{static_dir_ / "flow_history.csv", "flow_"},
        std::pair{model_dir() / "history.csv", "joint_"}}) {
    if (!fs::exists(history)) continue;
    runs.push_back({history, {"--history", history.string(), "--out",
                              plots.string(), "--prefix", prefix}});
  }
  return runs;
}

}  // namespace es
