#ifndef EULERSPLAT_SYNTH_PRESET_H_
#define EULERSPLAT_SYNTH_PRESET_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "synth/camera.h"
#include "synth/flow.h"
#include "synth/scenery.h"
#include "synth/water.h"

namespace es {

// What a camera adds to the splats when it films them as a path tracer
// renders: motion blur and per-pixel sample noise (1 and 0: none, the
// plain splat look).
struct SynthCameraEffects {
  int motion_blur_samples = 1;  // renders averaged per frame
  double shutter = 0.5;         // open for this fraction of a frame
  double noise = 0.0;           // per-pixel noise std (colour in [0, 1])
};

// Everything that makes one kind of synthetic water scene: the field, the
// particle stream, the scenery around it and the camera move that frames it.
struct SynthPreset {
  std::string name;
  SynthFlow flow;
  WaterSimOptions water;  // seed, stochasticity, substeps: set by the caller
  WaterLook look;
  SceneryLayout scenery;
  CameraPathSpec camera;
  SynthCameraEffects effects;
  Eigen::Vector3d background{0.72, 0.80, 0.88};  // sky
  int warmup_frames = 120;  // simulated before frame 0: a developed stream
};

std::vector<std::string> SynthPresetNames();

// `detail` scales the Gaussian counts (1: full scenes; tests use ~0.05):
// particle and scenery counts grow with it, sizes shrink so coverage stays.
// `seed` places the rocks. Throws InputError for an unknown name.
SynthPreset MakeSynthPreset(const std::string& name, double detail,
                            uint64_t seed);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_PRESET_H_
