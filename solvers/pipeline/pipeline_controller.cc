#include "solvers/pipeline/pipeline_controller.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/base/input_error.h"
#include "core/io/colmap_io.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/model/dynamic_set.h"
#include "solvers/pipeline/preset_choice.h"
#include "solvers/pipeline/run_lock.h"
#include "solvers/pipeline/run_sheet.h"
#include "solvers/pipeline/scene_inputs.h"

namespace es {
namespace {

namespace fs = std::filesystem;

// eulersplat --ranks / --batch_frames: how es_static and es_train start.
RankLaunch RankLaunchOf(const PipelineOptions& o) {
  RankLaunch r;
  r.ranks = o.ranks;
  r.batch_frames = o.batch_frames > 0 ? o.batch_frames : o.ranks;
  if (o.ranks > 1) {
    r.mpiexec = FindMpiexec();
    if (r.mpiexec.empty()) {
      throw InputError("--ranks " + std::to_string(o.ranks) +
                       ": mpiexec is not on PATH (Debian: apt-get install "
                       "openmpi-bin)");
    }
    // The machine's cores shared between the ranks, unless the caller
    // set OMP_NUM_THREADS (mpiexec passes the environment on).
    if (std::getenv("OMP_NUM_THREADS") == nullptr) {
      r.threads_per_rank = std::max(
          1, static_cast<int>(std::thread::hardware_concurrency()) / o.ranks);
    }
  }
  return r;
}

// The clip as the stages will read it: frames and the widest camera.
ClipSize ReadClipSize(const fs::path& scene) {
  const ColmapModel model = ReadColmapModel((scene / "sparse" / "0").string());
  ClipSize clip;
  clip.frames = static_cast<int>(model.images.size());
  for (const auto& [id, camera] : model.cameras) {
    if (camera.width > clip.width) {
      clip.width = camera.width;
      clip.height = camera.height;
    }
  }
  return clip;
}

}  // namespace

PipelineController::PipelineController(const PipelineOptions& options)
    : options_(options), plan_(options), runner_(options.device) {
  if (options.ranks > 1 || options.batch_frames > 1)
    runner_.SetRanks(RankLaunchOf(options));
}

void PipelineController::RunStep(const StageStep& step, StageLog* log) const {
  log->Begin(step.title);
  if (StepIsDone(step)) {
    log->Skipped();
    std::printf("\n[%s] skipped: outputs exist in %s (delete them to redo)\n",
                step.label.c_str(), step.where.string().c_str());
    return;
  }
  std::printf("%s", step.note.c_str());
  if (step.on_failure.empty()) {
    runner_.RunOrThrow("[" + step.label + "]", step.binary, step.args);
  } else if (runner_.Run(step.binary, step.args) != 0) {
    std::printf("%s", step.on_failure.c_str());
  }
}

// The training histories as PNGs in OUT/plots, redrawn on every run
// (cheap). A failure only costs the plots.
void PipelineController::RunPlots(StageLog* log) const {
  log->Begin("training plots (es_plot)");
  for (const auto& [history, args] : plan_.PlotRuns()) {
    if (runner_.Run("es_plot", args) != 0) {
      std::printf("[plots] es_plot failed on %s (see above)\n",
                  history.string().c_str());
    }
  }
}

bool PipelineController::HasDynamicGaussians() const {
  const int num_dynamic = static_cast<int>(
      DynamicSet(ReadPly(plan_.static_ply().string()),
                 options_.dynamic_threshold)
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
      options_.dynamic_threshold, plan_.static_ply().string().c_str());
  if (!plan_.has_masks()) {
    std::printf("[eulersplat] the scene has no masks/: without them "
                "Stage 1 has no mask (BCE) term and marks no Gaussian as "
                "water. Add masks/ (same file names, white = water) to "
                "animate it.\n");
  }
  return false;
}

// Checked before Stage 1, not in Stage 3: a loop longer than the video
// would fail only after Stage 1 had trained.
void PipelineController::CheckCycleLength(const fs::path& scene) const {
  const int num_frames = static_cast<int>(
      ReadColmapModel((scene / "sparse" / "0").string()).images.size());
  if (options_.cycle_length > num_frames) {
    throw InputError("--cycle_length=" + std::to_string(options_.cycle_length) +
                     ": must be <= " + std::to_string(num_frames) + " (" +
                     scene.string() + " has " + std::to_string(num_frames) +
                     " frames)");
  }
}

void PipelineController::ChoosePresetFor(const fs::path& scene) {
  preset_name_ = options_.preset;
  if (options_.preset != "auto") return;
  Hardware hardware;
  hardware.threads = options_.threads;
  hardware.gpu = options_.device != "cpu";
  const PresetChoice choice =
      ChoosePreset(ReadClipSize(scene), options_, hardware);
  plan_.SetPreset(choice.preset);
  preset_name_ = choice.name;
  preset_why_ = choice.why;
  predicted_seconds_ = choice.predicted_seconds;
  std::printf("\n[eulersplat] --preset auto chose %s\n", choice.why.c_str());
}

void PipelineController::WriteTimings(StageLog* log) const {
  nlohmann::ordered_json json = {{"preset", preset_name_},
                                 {"threads", options_.threads}};
  if (!preset_why_.empty()) {
    json["preset_auto"] = {{"why", preset_why_},
                           {"predicted_seconds", predicted_seconds_}};
  }
  json.update(log->Finish());
  const fs::path path = plan_.out() / "timings.json";
  WriteJsonFile(path.string(), json);
  std::printf("[eulersplat] seconds per stage: %s\n", path.c_str());
}

void PipelineController::Run() {
  const auto start = std::chrono::steady_clock::now();
  PrepareOutputDirectory(options_.out, "out");
  // One run per output folder; runs sharing a static_dir take turns on it
  // until its Stages 1 and 2 are written.
  const RunLock out_lock(plan_.out().string(), RunLock::Mode::kFailIfHeld);
  std::optional<RunLock> static_lock;
  if (!options_.static_dir.empty()) {
    static_lock.emplace(plan_.static_dir().string(),
                        RunLock::Mode::kWaitIfHeld);
  }
  const StageRunner run_or_throw = [this](const std::string& stage,
                                          const std::string& binary,
                                          const std::vector<std::string>& a) {
    runner_.RunOrThrow(stage, binary, a);
  };
  const fs::path scene = PrepareFramesAndPoses(options_, run_or_throw);
  ChoosePresetFor(scene);
  const double scale = ImageScaleFor(options_, plan_.preset(), scene);
  CheckCycleLength(scene);
  plan_.SetScene(scene, scale);
  const PreparedScene prepared = PrepareMasks(
      options_, scene, plan_.MaskProbeSettings(), run_or_throw);
  plan_.SetHasMasks(prepared.has_masks);
  // static, flow, joint, export, eval, plots (+ two videos, contact sheet).
  StageLog log(prepared.static_only ? 1 : 6 + (options_.animate ? 3 : 0),
               std::chrono::duration<double>(
                   std::chrono::steady_clock::now() - start)
                   .count());
  const Preset& p = plan_.preset();
  std::printf("\n[eulersplat] preset %s: %d static / %d flow / %d joint "
              "iterations, L = %d, image scale %.3g, masks %s\n",
              preset_name_.c_str(), p.static_iterations, p.flow_iterations,
              p.joint_iterations, options_.cycle_length, scale,
              prepared.has_masks ? "yes" : "no");

  if (prepared.static_only) {
    std::printf("[eulersplat] %s: training the static model only (no "
                "motion field, loop or animation)\n",
                prepared.why_static.c_str());
    RunStep(plan_.StaticStep(), &log);
    WriteTimings(&log);
    std::printf("\n[eulersplat] done: static model %s\n",
                plan_.static_ply().c_str());
    return;
  }
  RunStep(plan_.StaticStep(), &log);
  if (!HasDynamicGaussians()) {
    WriteTimings(&log);
    return;
  }
  RunStep(plan_.FlowStep(), &log);
  // Stages 1 and 2 are on disk and the later stages only read them: other
  // runs sharing the static_dir (ablations, seeds) may go on alongside.
  static_lock.reset();
  RunStep(plan_.JointStep(), &log);
  if (options_.animate) {
    for (const StageStep& video : plan_.AnimateSteps()) RunStep(video, &log);
  }
  RunStep(plan_.ExportStep(), &log);
  RunStep(plan_.EvalStep(), &log);
  RunPlots(&log);
  if (options_.animate) {
    log.Begin("contact sheet");
    WriteRunContactSheet(plan_.out(), options_.cycle_length);
  }
  WriteTimings(&log);
  PrintSummary(std::chrono::duration<double>(
                   std::chrono::steady_clock::now() - start)
                   .count());
}

void PipelineController::PrintSummary(double seconds) const {
  const fs::path& out = plan_.out();
  std::printf("\n[eulersplat] done in %.0f s\n  metrics        %s\n"
              "  plots          %s\n",
              seconds, (plan_.eval_dir() / "eval.json").c_str(),
              (out / "plots").c_str());
  if (options_.animate) {
    std::printf("  looping video  %s\n  fixed view     %s\n"
                "  contact sheet  %s\n",
                (out / "animate" / "animation.mp4").c_str(),
                (out / "animate_fixed" / "animation.mp4").c_str(),
                (out / "contact_sheet.png").c_str());
  }
  if (fs::exists(out / "web" / "view.json")) {
    std::printf("  web page       %s (python3 -m http.server --directory "
                "%s, then open localhost:8000)\n",
                (out / "web" / "index.html").c_str(), (out / "web").c_str());
  }
}

}  // namespace es
