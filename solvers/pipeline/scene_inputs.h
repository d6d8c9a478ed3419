#ifndef EULERSPLAT_SOLVERS_PIPELINE_SCENE_INPUTS_H_
#define EULERSPLAT_SOLVERS_PIPELINE_SCENE_INPUTS_H_

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "solvers/pipeline/pipeline_options.h"

namespace es {

// Runs a stage binary (as the driver does) and throws when it fails.
using StageRunner =
    std::function<void(const std::string& stage, const std::string& binary,
                       const std::vector<std::string>& args)>;

// Settings of the first static fit the auto masks are found with.
struct MaskProbe {
  int iterations = 300;
  std::vector<std::string> static_flags;  // e.g. --image_scale, --sh_degree
  std::vector<std::string> mask_flags;    // extra es_masks flags
};

struct PreparedScene {
  std::filesystem::path scene;  // what every stage reads
  bool has_masks = false;
  bool static_only = false;     // nothing moves (or --masks none)
  std::string why_static;       // the message to print when static_only
};

// Makes a scene every stage can read: a video is decoded into OUT/scene;
// a scene that lacks what the run needs (poses, masks) is viewed through
// OUT/scene (links to its images/, sparse/, split.txt, gt/, never written
// into); then poses with COLMAP when sparse/0 is missing. Each step is
// skipped when its outputs exist. Throws InputError on bad input.
std::filesystem::path PrepareFramesAndPoses(const PipelineOptions& request,
                                            const StageRunner& run);

// Masks for `scene` as request.masks says; "auto" runs the probe (a static
// fit without masks into OUT/mask_probe, then es_masks writing
// scene/masks, OUT/masks_sheet.png and OUT/masks_report.json).
PreparedScene PrepareMasks(const PipelineOptions& request,
                           const std::filesystem::path& scene,
                           const MaskProbe& probe, const StageRunner& run);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_SCENE_INPUTS_H_
