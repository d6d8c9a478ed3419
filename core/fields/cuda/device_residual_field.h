#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_

// The residual field D (ResidualField, core/fields/residual_field.h) on
// device arrays: MLP(triplane(x0), encodings of t and p) times its output
// scales, kResidualDim outputs per point, evaluated and differentiated as
// the CPU field is, in double. FieldParams and FieldGradients hold device
// pointers (triplane_chunks must be null). No CUDA types; failures throw
// CudaError.

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_mlp.h"
#include "core/fields/cuda/device_triplane.h"
#include "core/fields/residual_field.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceResidualField {
 public:
  // `field`'s shape, box, encodings and output scales as they are now.
  explicit DeviceResidualField(const ResidualField& field);

  const DeviceTriplane& triplane() const { return triplane_; }
  const DeviceMlp& mlp() const { return mlp_; }

  // out (n x kResidualDim) = D(x0 (n x 3), t (n), p (n)); all device
  // arrays, t and p ints.
  void Evaluate(const FieldParams& params, int n, const double* x0,
                const int* t, const int* p, double* out,
                DeviceFieldWorkspace* ws) const;
  // Backward of the last Evaluate on *ws: given d_out (n x kResidualDim),
  // accumulates parameter gradients and dL/dx0 (n x 3, nullable).
  void Backward(const FieldParams& params, const double* d_out,
                const FieldGradients& grads, double* d_x0,
                DeviceFieldWorkspace* ws) const;

 private:
  DeviceTriplane triplane_;
  DeviceMlp mlp_;
  ResidualFieldOptions options_;
  DeviceBuffer<double> scales_;  // per output
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_
