#ifndef EULERSPLAT_TESTS_SMALL_MOTION_FIELD_H_
#define EULERSPLAT_TESTS_SMALL_MOTION_FIELD_H_

#include <cstdint>

#include <Eigen/Core>

#include "core/fields/motion_field.h"

namespace es {

// A small field over the box [-1, 1]^3 that moves points noticeably: up to
// a few percent of the box per step at velocity_scale 0.02 (R = 8, 4
// channels, width 16, outputs far from zero).
inline MotionField SmallMotionField(uint32_t seed,
                                    double velocity_scale = 0.02) {
  MotionFieldOptions options;
  options.triplane.resolution = 8;
  options.triplane.channels = 4;
  options.triplane.init_noise = 0.5;
  options.mlp_width = 16;
  options.last_layer_init_scale = 1.0;
  options.velocity_scale = velocity_scale;
  MotionField field(options);
  field.SetBox(Eigen::Vector3d(-1.0, -1.0, -1.0),
               Eigen::Vector3d(1.0, 1.0, 1.0));
  field.Initialize(seed);
  return field;
}

// SmallMotionField(seed) with its output layer's weights (not its biases)
// scaled to ~1e300: velocities overflow or are enormous, for the Euler
// chain's stress rule.
inline MotionField OverflowingMotionField(uint32_t seed) {
  MotionField field = SmallMotionField(seed);
  const int num_mlp = static_cast<int>(field.mlp_params().size());
  for (int i = num_mlp - 3 - 3 * 16; i < num_mlp - 3; ++i) {
    field.mlp_params()[i] *= 1e300;
  }
  return field;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_SMALL_MOTION_FIELD_H_
