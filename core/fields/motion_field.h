#ifndef EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_

#include <cstdint>

#include <Eigen/Core>

#include "core/fields/triplane_mlp_field.h"

namespace es {

struct MotionFieldOptions {
  TriplaneOptions triplane;  // defaults: 128^2 x 12, product
  int mlp_width = 64;
  int mlp_depth = 2;  // hidden layers
  // V = velocity_scale * box diagonal * MLP output, so an MLP output of 1
  // moves a point by velocity_scale of the box diagonal per frame whatever
  // the scene's units: initialization and learning rates are scale-free.
  double velocity_scale = 0.01;
  // Output layer weights start this much smaller than Kaiming, so V ~ 0.
  double last_layer_init_scale = 0.01;
  uint32_t seed = 1;
};

// The static Eulerian velocity field V: R^3 -> R^3, V(x) = output_scale() *
// MLP(triplane(x)), displacement per frame in world units.
class MotionField : public TriplaneMlpField<3> {
 public:
  explicit MotionField(const MotionFieldOptions& options);

  // Sets the box (normally the dynamic Gaussians' bounds) the triplane spans
  // and that the output scale follows. Parameters are kept.
  void SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

  const MotionFieldOptions& options() const { return options_; }
  // velocity_scale * box diagonal * the displacement factor.
  double output_scale() const;
  // Scales V's output, and so each Euler step: Stage 3's motion warm-up
  // starts the water at factor 0, where the loop is Stage 1's model, and
  // raises it to 1. Not saved with the field: a loaded field moves at 1.
  void SetDisplacementFactor(double factor);
  double displacement_factor() const { return displacement_factor_; }

  // v (n x 3) = V(x (n x 3)), keeping state in *ws for Backward (inherited:
  // given d_v (n x 3), accumulates parameter gradients and dL/dx).
  void Evaluate(const FieldParams& p, int n, const double* x, double* v,
                FieldWorkspace* ws) const;

 private:
  // Every output scale becomes output_scale().
  void UpdateOutputScales();

  MotionFieldOptions options_;
  double displacement_factor_ = 1.0;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_MOTION_FIELD_H_
