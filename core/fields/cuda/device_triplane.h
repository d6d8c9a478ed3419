#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_H_

// Triplane (core/fields/triplane.h) sampling and backward on device arrays:
// the same parameter layout, texel mapping, border clamp and non-finite
// rule, in double. No CUDA types; failures throw CudaError.

#include "core/fields/cuda/field_kernels.h"
#include "core/fields/triplane.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

class DeviceTriplane {
 public:
  // `triplane`'s options and box as they are now (a later SetBox on it is
  // not seen).
  explicit DeviceTriplane(const Triplane& triplane);

  int output_dim() const { return output_dim_; }
  int num_params() const { return num_params_; }

  // Triplane::Sample on device arrays (params, x: n x 3, out).
  void Sample(const double* params, int n, const double* x, double* out,
              int out_stride = 0) const;
  // Triplane::Backward on device arrays: accumulates into d_params and d_x
  // (either may be nullptr).
  void Backward(const double* params, int n, const double* x,
                const double* d_out, double* d_params, double* d_x,
                int d_out_stride = 0) const;
  // Triplane::TotalVariation on device params: returns the value (the one
  // double that comes back) and accumulates its gradient into d_params
  // (nullable). *scratch holds the partial sums (it only grows).
  double TotalVariation(const double* params, double weight,
                        double* d_params, DeviceBuffer<double>* scratch) const;

 private:
  TriplaneGeometry geometry_;
  int output_dim_, num_params_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_TRIPLANE_H_
