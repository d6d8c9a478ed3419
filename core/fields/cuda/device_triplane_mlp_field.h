#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_MLP_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_MLP_FIELD_H_

// TriplaneMlpField (core/fields/triplane_mlp_field.h) on device arrays, the
// base of DeviceMotionField and DeviceResidualField: the same evaluation
// halves and Backward, in double. FieldParams and FieldGradients hold
// device pointers here (triplane_chunks must be null: the device gradient
// is dense). No CUDA types; failures throw CudaError.

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_mlp.h"
#include "core/fields/cuda/device_triplane.h"
#include "core/fields/triplane_mlp_field.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceTriplaneMlpField {
 public:
  const DeviceTriplane& triplane() const { return triplane_; }
  const DeviceMlp& mlp() const { return mlp_; }

  // TriplaneMlpField::Backward of the last Evaluate on *ws, device arrays.
  void Backward(const FieldParams& p, const double* d_out,
                const FieldGradients& grads, double* d_x,
                DeviceFieldWorkspace* ws) const;

 protected:
  // `field`'s shape, box and output scales as they are now (its parameter
  // values are passed to each call); `name` (a literal, the derived
  // class's) starts the CHECK messages.
  template <int kOutputs>
  DeviceTriplaneMlpField(const char* name,
                         const TriplaneMlpField<kOutputs>& field)
      : DeviceTriplaneMlpField(name, field.triplane(), field.mlp(),
                               field.output_scales().data()) {}

  // TriplaneMlpField::SampleFeatures and ForwardScaled on device arrays.
  void SampleFeatures(const FieldParams& p, int n, const double* x,
                      DeviceFieldWorkspace* ws) const;
  void ForwardScaled(const FieldParams& p, double* out,
                     DeviceFieldWorkspace* ws) const;

 private:
  // output_scales: mlp.output_dim() host values.
  DeviceTriplaneMlpField(const char* name, const Triplane& triplane,
                         const Mlp& mlp, const double* output_scales);

  const char* name_;
  DeviceTriplane triplane_;
  DeviceMlp mlp_;
  DeviceBuffer<double> scales_;  // per output
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_MLP_FIELD_H_
