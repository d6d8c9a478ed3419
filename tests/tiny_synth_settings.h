#ifndef EULERSPLAT_TESTS_TINY_SYNTH_SETTINGS_H_
#define EULERSPLAT_TESTS_TINY_SYNTH_SETTINGS_H_

#include <string>

#include "synth/scene.h"

namespace es {

// A synthetic scene small enough to build in well under a second.
inline SynthSettings TinySynthSettings(const std::string& preset = "waterfall",
                                       int frames = 10) {
  SynthSettings s;
  s.preset = preset;
  s.frames = frames;
  s.width = 64;
  s.height = 48;
  s.detail = 0.03;
  s.seed = 7;
  s.grid_resolution = 8;
  s.num_points = 200;
  return s;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_TINY_SYNTH_SETTINGS_H_
