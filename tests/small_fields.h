#ifndef EULERSPLAT_TESTS_SMALL_FIELDS_H_
#define EULERSPLAT_TESTS_SMALL_FIELDS_H_

#include "core/fields/motion_field.h"
#include "core/fields/residual_field.h"
#include "core/fields/triplane.h"

namespace es {

// The triplane of the field and triplane tests: 8 x 8 planes of `channels`
// features, combined by `combination`, noisy enough that every plane
// matters.
inline TriplaneOptions SmallPlanes(PlaneCombination combination,
                                   int channels = 4) {
  TriplaneOptions options;
  options.resolution = 8;
  options.channels = channels;
  options.combination = combination;
  options.init_noise = 0.5;
  return options;
}

// Small fields (R = 8, 4 channels, width 16) whose outputs are far from
// zero, for the tests of a moving, recolored loop.
inline MotionFieldOptions SmallMotionFieldOptions(double velocity_scale) {
  MotionFieldOptions mo;
  mo.triplane.resolution = 8;
  mo.triplane.channels = 4;
  mo.mlp_width = 16;
  mo.velocity_scale = velocity_scale;
  mo.last_layer_init_scale = 1.0;
  return mo;
}

inline ResidualFieldOptions SmallResidualFieldOptions(int cycle_length) {
  ResidualFieldOptions ro;
  ro.triplane.resolution = 8;
  ro.triplane.channels = 4;
  ro.cycle_length = cycle_length;
  ro.mlp_width = 16;
  ro.last_layer_init_scale = 0.3;
  return ro;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_SMALL_FIELDS_H_
