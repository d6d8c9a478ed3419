#ifndef EULERSPLAT_SOLVERS_PIPELINE_PRESET_H_
#define EULERSPLAT_SOLVERS_PIPELINE_PRESET_H_

#include <filesystem>
#include <string>

#include "solvers/pipeline/pipeline_options.h"

namespace es {

// The sizes and lengths of one run's stages.
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

// "quick" or "paper"; throws InputError naming --preset otherwise ("auto"
// is chosen from the clip: preset_choice.h).
Preset MakePreset(const std::string& name);

// Throws InputError naming --preset unless `name` is auto, quick or paper.
void CheckPresetName(const std::string& name);

// `preset` with the options' iteration overrides (those >= 0).
Preset WithOverrides(Preset preset, const PipelineOptions& options);

// options.preset with the options' iteration overrides; "auto" is quick
// until the clip is known (StagePlan::SetPreset).
Preset PresetFor(const PipelineOptions& options);

// The image scale the stages train at: options.image_scale when set (> 0),
// else what keeps the widest camera of scene/sparse/0 at most
// preset.max_width wide.
double ImageScaleFor(const PipelineOptions& options, const Preset& preset,
                     const std::filesystem::path& scene);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_PRESET_H_
