#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_

// The velocity field V (MotionField, core/fields/motion_field.h) on device
// arrays: V(x) = output_scale * MLP(triplane(x)), evaluated and
// differentiated (Backward: DeviceTriplaneMlpField's) as the CPU field is,
// in double. No CUDA types; failures throw CudaError.

#include "core/fields/cuda/device_triplane_mlp_field.h"
#include "core/fields/motion_field.h"

namespace es {
namespace cuda {

class DeviceMotionField : public DeviceTriplaneMlpField {
 public:
  // `field`'s shape, box and output scale as they are now (its parameter
  // values are passed to each call).
  explicit DeviceMotionField(const MotionField& field);

  double box_diagonal() const { return box_diagonal_; }
  double output_scale() const { return output_scale_; }

  // v (n x 3) = V(x (n x 3)), device arrays; keeps state in *ws.
  void Evaluate(const FieldParams& p, int n, const double* x, double* v,
                DeviceFieldWorkspace* ws) const;

 private:
  double box_diagonal_, output_scale_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_
