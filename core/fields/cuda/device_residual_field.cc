#include "core/fields/cuda/device_residual_field.h"

#include "core/fields/cuda/field_kernels.h"

namespace es {
namespace cuda {

DeviceResidualField::DeviceResidualField(const ResidualField& field)
    : DeviceTriplaneMlpField("DeviceResidualField", field),
      options_(field.options()) {}

void DeviceResidualField::Evaluate(const FieldParams& params, int n,
                                   const double* x0, const int* t,
                                   const int* p, double* out,
                                   DeviceFieldWorkspace* ws) const {
  SampleFeatures(params, n, x0, ws);
  EncodeCycleKernel(n, t, p, options_.t_frequencies, options_.cycle_length,
                    options_.p_frequencies, 2.0 * options_.max_cycles,
                    ws->features.data(), mlp().input_dim(),
                    triplane().output_dim());
  ForwardScaled(params, out, ws);
}

}  // namespace cuda
}  // namespace es
