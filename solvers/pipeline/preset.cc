#include "solvers/pipeline/preset.h"

#include <algorithm>

#include "core/base/input_error.h"
#include "core/io/colmap_io.h"

namespace es {

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
  throw InputError("--preset: unknown preset '" + name +
                   "' (auto, quick or paper)");
}

void CheckPresetName(const std::string& name) {
  if (name != "auto") MakePreset(name);
}

Preset PresetFor(const PipelineOptions& options) {
  return WithOverrides(
      MakePreset(options.preset == "auto" ? "quick" : options.preset),
      options);
}

Preset WithOverrides(Preset p, const PipelineOptions& options) {
  if (options.static_iterations >= 0) {
    p.static_iterations = options.static_iterations;
  }
  if (options.flow_iterations >= 0) p.flow_iterations = options.flow_iterations;
  if (options.joint_iterations >= 0) {
    p.joint_iterations = options.joint_iterations;
  }
  return p;
}

double ImageScaleFor(const PipelineOptions& options, const Preset& preset,
                     const std::filesystem::path& scene) {
  if (options.image_scale > 0) return options.image_scale;
  if (preset.max_width <= 0) return 1.0;
  const ColmapModel model = ReadColmapModel((scene / "sparse" / "0").string());
  int width = 0;
  for (const auto& [id, camera] : model.cameras) {
    width = std::max(width, camera.width);
  }
  return width > preset.max_width
             ? static_cast<double>(preset.max_width) / width
             : 1.0;
}

}  // namespace es
