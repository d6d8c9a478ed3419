#ifndef EULERSPLAT_TESTS_SMALL_FIELDS_H_
#define EULERSPLAT_TESTS_SMALL_FIELDS_H_

#include <cstdint>

#include <Eigen/Core>

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

// The field tests' box: not a cube, not at the origin.
inline const Eigen::Vector3d kFieldTestBoxMin(-2.0, -1.0, 0.0);
inline const Eigen::Vector3d kFieldTestBoxMax(2.0, 1.0, 3.0);

// A motion field on `planes` with an MLP `width` wide whose outputs are far
// from zero (velocity scale 0.1), over the field tests' box, drawn from
// `seed`: the subject of the gradient and CPU-vs-device tests.
inline MotionField TestMotionField(const TriplaneOptions& planes, int width,
                                   uint32_t seed) {
  MotionFieldOptions options;
  options.triplane = planes;
  options.mlp_width = width;
  options.last_layer_init_scale = 1.0;
  options.velocity_scale = 0.1;
  MotionField field(options);
  field.SetBox(kFieldTestBoxMin, kFieldTestBoxMax);
  field.Initialize(seed);
  return field;
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
