#ifndef EULERSPLAT_SOLVERS_PIPELINE_STAGE_PLAN_H_
#define EULERSPLAT_SOLVERS_PIPELINE_STAGE_PLAN_H_

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "solvers/pipeline/pipeline_options.h"
#include "solvers/pipeline/preset.h"
#include "solvers/pipeline/scene_inputs.h"

namespace es {

// One run of a stage binary in the driver's plan, with what decides
// whether it runs at all.
struct StageStep {
  std::string title;  // in the stage log: "static model (es_static)"
  // "static": in the skip message, and "[static]" in a failure's.
  std::string label;
  std::filesystem::path where;  // the folder the skip message names
  std::vector<std::filesystem::path> outputs;  // all present: skipped
  std::string binary;
  std::vector<std::string> args;
  // Empty: a failure ends the run. Otherwise the line printed when the
  // stage fails, and the run goes on without its outputs.
  std::string on_failure;
  std::string note;  // printed before the stage runs (empty: nothing)
};

// True when every output of `step` exists: the stage has run already.
bool StepIsDone(const StageStep& step);

// The stages of one run, each as the binary and flags it runs with, built
// from the options and the preset. A step is built right before it runs:
// some flags depend on what the stages before it wrote (a checkpoint to
// resume from, Stage 2's V to compare with).
class StagePlan {
 public:
  // Throws InputError for an unknown preset (PresetFor).
  explicit StagePlan(const PipelineOptions& options);

  // Replaces the preset (--preset auto's choice, overrides applied).
  void SetPreset(const Preset& preset) { preset_ = preset; }

  // The scene every stage reads, and the image scale they train at.
  void SetScene(const std::filesystem::path& scene, double image_scale);
  void SetHasMasks(bool has_masks) { has_masks_ = has_masks; }

  const Preset& preset() const { return preset_; }
  bool has_masks() const { return has_masks_; }
  const std::filesystem::path& out() const { return out_; }
  const std::filesystem::path& static_dir() const { return static_dir_; }
  std::filesystem::path static_ply() const {
    return static_dir_ / "static.ply";
  }
  std::filesystem::path model_dir() const { return out_ / "model"; }
  std::filesystem::path eval_dir() const { return out_ / "eval"; }

  // Stage 1's flags but --out and --iterations (shared with the probe).
  std::vector<std::string> StaticFlags() const;
  // The static fit the auto masks are found with.
  MaskProbe MaskProbeSettings() const;

  StageStep StaticStep() const;  // Stage 1, es_static
  StageStep FlowStep() const;    // Stage 2, es_flowinit
  StageStep JointStep() const;   // Stage 3, es_train
  // The two videos: along the input trajectory with tracks, and a fixed
  // view with its x-t slice.
  std::vector<StageStep> AnimateSteps() const;
  StageStep ExportStep() const;  // the web page and frame-0 PLY
  StageStep EvalStep() const;
  // es_plot's flags for each training history that exists, with it.
  std::vector<std::pair<std::filesystem::path, std::vector<std::string>>>
  PlotRuns() const;

 private:
  // --scene, --image_scale, `extra`, then --white_background if `render`.
  std::vector<std::string> Args(const std::vector<std::string>& extra,
                                bool render) const;

  PipelineOptions options_;
  Preset preset_;
  std::filesystem::path out_, static_dir_;
  bool has_masks_ = false;
  std::vector<std::string> common_;      // --scene, --image_scale
  std::vector<std::string> background_;  // --white_background or nothing
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_STAGE_PLAN_H_
