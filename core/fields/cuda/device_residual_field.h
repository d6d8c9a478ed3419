#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_

// The residual field D (ResidualField, core/fields/residual_field.h) on
// device arrays: MLP(triplane(x0), encodings of t and p) times its output
// scales, kResidualDim outputs per point, evaluated and differentiated
// (Backward: DeviceTriplaneMlpField's) as the CPU field is, in double. No
// CUDA types; failures throw CudaError.

#include "core/fields/cuda/device_triplane_mlp_field.h"
#include "core/fields/residual_field.h"

namespace es {
namespace cuda {

class DeviceResidualField : public DeviceTriplaneMlpField {
 public:
  // `field`'s shape, box, encodings and output scales as they are now.
  explicit DeviceResidualField(const ResidualField& field);

  // out (n x kResidualDim) = D(x0 (n x 3), t (n), p (n)); all device
  // arrays, t and p ints.
  void Evaluate(const FieldParams& params, int n, const double* x0,
                const int* t, const int* p, double* out,
                DeviceFieldWorkspace* ws) const;

 private:
  ResidualFieldOptions options_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_RESIDUAL_FIELD_H_
