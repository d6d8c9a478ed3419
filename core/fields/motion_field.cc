#include "core/fields/motion_field.h"

#include "core/base/stage_profile.h"

namespace es {

MotionField::MotionField(const MotionFieldOptions& options)
    : TriplaneMlpField("MotionField", options.triplane, /*extra_inputs=*/0,
                       options.mlp_width, options.mlp_depth,
                       options.last_layer_init_scale, options.seed),
      options_(options) {
  UpdateOutputScales();
}

void MotionField::SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  SetTriplaneBox(lo, hi);
  UpdateOutputScales();
}

double MotionField::output_scale() const {
  return options_.velocity_scale * box_diagonal() * displacement_factor_;
}

void MotionField::SetDisplacementFactor(double factor) {
  displacement_factor_ = factor;
  UpdateOutputScales();
}

void MotionField::UpdateOutputScales() {
  SetOutputScales(0, 3, output_scale());
}

void MotionField::Evaluate(const FieldParams& p, int n, const double* x,
                           double* v, FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsForward);
  SampleFeatures(p, n, x, ws);
  ForwardScaled(p, v, ws);
}

}  // namespace es
