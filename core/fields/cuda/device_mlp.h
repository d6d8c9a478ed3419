#ifndef EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MLP_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MLP_H_

// Mlp (core/fields/mlp.h) forward and backward on device arrays: ReLU
// hidden layers, a linear output layer, the same weight layout (W_l out x
// in row-major, then b_l, layer after layer), in double. No CUDA types;
// failures throw CudaError.

#include <vector>

#include "core/fields/mlp.h"
#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Activations of one Forward kept for Backward, and the backward scratch;
// buffers only grow.
struct DeviceMlpWorkspace {
  int batch = 0;
  const double* input = nullptr;  // device, not owned; must outlive Backward
  std::vector<DeviceBuffer<double>> hidden;  // post-ReLU, batch x width
  DeviceBuffer<double> grad, grad_prev;      // dL/d(layer output)
};

class DeviceMlp {
 public:
  explicit DeviceMlp(const Mlp& mlp);

  int input_dim() const { return input_dim_; }
  int output_dim() const { return output_dim_; }
  int width() const { return width_; }
  int depth() const { return depth_; }
  int num_params() const { return offsets_.back(); }

  // out (n x output_dim) = MLP(input (n x input_dim)), device arrays.
  void Forward(const double* params, int n, const double* input, double* out,
               DeviceMlpWorkspace* ws) const;
  // Backward of the last Forward on *ws: accumulates dL/dparams into
  // d_params and dL/dinput into d_input (either may be nullptr).
  void Backward(const double* params, const double* d_out, double* d_params,
                double* d_input, DeviceMlpWorkspace* ws) const;

 private:
  int layer_in(int l) const { return l == 0 ? input_dim_ : width_; }
  int layer_out(int l) const { return l == depth_ ? output_dim_ : width_; }

  int input_dim_, width_, depth_, output_dim_;
  std::vector<int> offsets_;  // start of W_l; offsets_.back() = total size
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_DEVICE_MLP_H_
