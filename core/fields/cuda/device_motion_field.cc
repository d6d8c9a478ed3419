#include "core/fields/cuda/device_motion_field.h"

namespace es {
namespace cuda {

DeviceMotionField::DeviceMotionField(const MotionField& field)
    : DeviceTriplaneMlpField("DeviceMotionField", field),
      box_diagonal_(field.box_diagonal()),
      output_scale_(field.output_scale()) {}

void DeviceMotionField::Evaluate(const FieldParams& p, int n, const double* x,
                                 double* v, DeviceFieldWorkspace* ws) const {
  SampleFeatures(p, n, x, ws);
  ForwardScaled(p, v, ws);
}

}  // namespace cuda
}  // namespace es
