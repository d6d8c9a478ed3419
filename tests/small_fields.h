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

// Sets a field's triplane resolution and channels and its MLP width.
// `FieldOptions` is MotionFieldOptions or ResidualFieldOptions.
template <typename FieldOptions>
void SetFieldSize(int resolution, int channels, int width, FieldOptions* o) {
  o->triplane.resolution = resolution;
  o->triplane.channels = channels;
  o->mlp_width = width;
}

// Small fields (R = 8, 4 channels, width 16) whose outputs are far from
// zero, for the tests of a moving, recolored loop. `FieldOptions` is
// MotionFieldOptions or ResidualFieldOptions.
template <typename FieldOptions>
FieldOptions SmallFieldOptions(double last_layer_init_scale) {
  FieldOptions o;
  SetFieldSize(8, 4, 16, &o);
  o.last_layer_init_scale = last_layer_init_scale;
  return o;
}

inline MotionFieldOptions SmallMotionFieldOptions(double velocity_scale) {
  auto o = SmallFieldOptions<MotionFieldOptions>(1.0);
  o.velocity_scale = velocity_scale;
  return o;
}

inline ResidualFieldOptions SmallResidualFieldOptions(int cycle_length) {
  auto o = SmallFieldOptions<ResidualFieldOptions>(0.3);
  o.cycle_length = cycle_length;
  return o;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_SMALL_FIELDS_H_
