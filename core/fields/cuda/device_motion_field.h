#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_

// The velocity field V (MotionField, core/fields/motion_field.h) on device
// arrays: V(x) = output_scale * MLP(triplane(x)), evaluated and
// differentiated as the CPU field is, in double. FieldParams and
// FieldGradients hold device pointers here (triplane_chunks must be null:
// the device gradient is dense). No CUDA types; failures throw CudaError.

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_mlp.h"
#include "core/fields/cuda/device_triplane.h"
#include "core/fields/motion_field.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceMotionField {
 public:
  // `field`'s shape, box and output scale as they are now (its parameter
  // values are passed to each call).
  explicit DeviceMotionField(const MotionField& field);

  double box_diagonal() const { return box_diagonal_; }
  double output_scale() const { return output_scale_; }
  const DeviceTriplane& triplane() const { return triplane_; }
  const DeviceMlp& mlp() const { return mlp_; }

  // v (n x 3) = V(x (n x 3)), device arrays; keeps state in *ws.
  void Evaluate(const FieldParams& p, int n, const double* x, double* v,
                DeviceFieldWorkspace* ws) const;
  // Backward of the last Evaluate on *ws: given d_v (n x 3), accumulates
  // parameter gradients into grads and dL/dx into d_x (n x 3, nullable).
  void Backward(const FieldParams& p, const double* d_v,
                const FieldGradients& grads, double* d_x,
                DeviceFieldWorkspace* ws) const;

 private:
  DeviceTriplane triplane_;
  DeviceMlp mlp_;
  double box_diagonal_, output_scale_;
  DeviceBuffer<double> scales_;  // output_scale_ per velocity component
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MOTION_FIELD_H_
