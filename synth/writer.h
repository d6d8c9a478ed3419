#ifndef EULERSPLAT_SYNTH_WRITER_H_
#define EULERSPLAT_SYNTH_WRITER_H_

#include <string>

#include "synth/scene.h"

namespace es {

// Writes a synthetic scene in the project's input layout (docs/SYNTH.md):
//   images/frame_000000.png ...   8-bit RGB frames
//   masks/frame_000000.png ...    8-bit, 255 = water
//   sparse/0/{cameras,images,points3D}.txt
//   split.txt                     held-out frame names (core/io/split.h)
//   gt/velocity_grid.bin          see synth/velocity_grid.h
//   gt/depth/frame_000000.tiff    float32 camera z per pixel, 0 = none
//   gt/settings.json              generator settings and summary numbers
// Throws InputError naming the path that could not be written.
void WriteSynthScene(const SynthScene& scene, const std::string& dir);

// The gt/settings.json text (deterministic: no time stamps).
std::string SynthSettingsJson(const SynthScene& scene);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_WRITER_H_
