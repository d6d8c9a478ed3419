#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_FIELD_WORKSPACE_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_FIELD_WORKSPACE_H_

// What the device fields share: the state one Evaluate keeps for Backward
// (FieldWorkspace's, in device memory), and a field's parameter blocks
// uploaded to the device. No CUDA types.

#include <vector>

#include "core/fields/cuda/device_mlp.h"
#include "core/fields/triplane_mlp_field.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Buffers only grow, so no allocation after the first call at the largest
// batch.
struct DeviceFieldWorkspace {
  int batch = 0;
  const double* x = nullptr;  // device, not owned; must outlive Backward
  DeviceBuffer<double> features;  // MLP input, batch x its input dim
  DeviceBuffer<double> d_features, d_mlp_out;
  DeviceMlpWorkspace mlp;
};

// A field's two parameter blocks (or their gradients) in device memory.
struct DeviceFieldBlocks {
  DeviceBuffer<double> triplane, mlp;

  void Upload(const std::vector<double>& triplane_values,
              const std::vector<double>& mlp_values) {
    triplane.Upload(triplane_values);
    mlp.Upload(mlp_values);
  }
  // A field's host blocks of the given sizes (e.g. field.params(),
  // field.triplane().num_params(), field.mlp().num_params()).
  void Upload(const FieldParams& host, int triplane_size, int mlp_size) {
    triplane.Upload(host.triplane, triplane_size);
    mlp.Upload(host.mlp, mlp_size);
  }
  // Zeros of the given sizes (gradient accumulators).
  void Zeros(size_t triplane_size, size_t mlp_size) {
    triplane.Resize(triplane_size);
    triplane.Zero();
    mlp.Resize(mlp_size);
    mlp.Zero();
  }
  FieldParams params() const { return {triplane.data(), mlp.data()}; }
  FieldGradients gradients() { return {triplane.data(), mlp.data()}; }
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_FIELD_WORKSPACE_H_
