#ifndef EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_CONTROLLER_H_
#define EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_CONTROLLER_H_

#include "solvers/pipeline/pipeline_options.h"
#include "solvers/pipeline/stage_log.h"
#include "solvers/pipeline/stage_plan.h"
#include "solvers/pipeline/stage_process.h"

namespace es {

// One eulersplat run, from a video or a scene directory to a looping 4D
// model, its videos, metrics, plots and a contact sheet: frames and poses,
// masks, then the stages of StagePlan in turn, each a binary of its own
// (StageProcessRunner). A stage whose outputs exist is skipped, and
// interrupted training resumes from its checkpoint, so a rerun picks up
// where a killed one stopped. --preset auto picks the preset once the clip
// is known (preset_choice.h); OUT/timings.json has each stage's seconds. One run per output folder (RunLock); runs
// sharing a static_dir take turns on it until Stages 1 and 2 are written.
class PipelineController {
 public:
  // Throws InputError for an unknown preset. options.device must be a
  // value ParseDeviceFlag accepted ("cpu" or "cuda").
  explicit PipelineController(const PipelineOptions& options);

  // Runs every stage, prints where the results are. Throws InputError for
  // bad input and when a stage the later ones need fails.
  void Run();

 private:
  // Begins the stage in `log`, then skips it (outputs exist) or runs it.
  void RunStep(const StageStep& step, StageLog* log) const;
  void RunPlots(StageLog* log) const;
  // Says whether Stage 1 marked any Gaussian as water (else the run stops).
  bool HasDynamicGaussians() const;
  // Throws InputError when the loop is longer than the scene's video.
  void CheckCycleLength(const std::filesystem::path& scene) const;
  void PrintSummary(double seconds) const;
  // --preset auto: chooses from the clip in `scene` and the hardware, sets
  // the plan's preset and says why.
  void ChoosePresetFor(const std::filesystem::path& scene);
  // OUT/timings.json: the preset, then the log's seconds per stage.
  void WriteTimings(StageLog* log) const;

  PipelineOptions options_;
  StagePlan plan_;
  StageProcessRunner runner_;
  std::string preset_name_;  // the preset run (auto's choice)
  std::string preset_why_;   // auto's reason ("" for a named preset)
  double predicted_seconds_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_PIPELINE_CONTROLLER_H_
