#include "core/fields/cuda/device_triplane_mlp_field.h"

#include <glog/logging.h>

#include "core/fields/cuda/field_kernels.h"

namespace es {
namespace cuda {

DeviceTriplaneMlpField::DeviceTriplaneMlpField(const char* name,
                                               const Triplane& triplane,
                                               const Mlp& mlp,
                                               const double* output_scales)
    : name_(name), triplane_(triplane), mlp_(mlp) {
  scales_.Upload(output_scales, mlp_.output_dim());
}

void DeviceTriplaneMlpField::SampleFeatures(const FieldParams& p, int n,
                                            const double* x,
                                            DeviceFieldWorkspace* ws) const {
  const int in_dim = mlp_.input_dim();
  ws->batch = n;
  ws->x = x;
  ws->features.Resize(static_cast<size_t>(n) * in_dim);
  triplane_.Sample(p.triplane, n, x, ws->features.data(), in_dim);
}

void DeviceTriplaneMlpField::ForwardScaled(const FieldParams& p, double* out,
                                           DeviceFieldWorkspace* ws) const {
  const int n = ws->batch, dim = mlp_.output_dim();
  mlp_.Forward(p.mlp, n, ws->features.data(), out, &ws->mlp);
  ScaleColumnsKernel(static_cast<long long>(n) * dim, dim, scales_.data(), out,
                     out);
}

void DeviceTriplaneMlpField::Backward(const FieldParams& p,
                                      const double* d_out,
                                      const FieldGradients& grads, double* d_x,
                                      DeviceFieldWorkspace* ws) const {
  CHECK(ws->x != nullptr) << name_ << "::Backward before Evaluate";
  CHECK(grads.triplane_chunks == nullptr)
      << "the device triplane gradient is dense: no chunk flags";
  const int n = ws->batch, dim = mlp_.output_dim();
  const int in_dim = mlp_.input_dim();
  const long long outputs = static_cast<long long>(n) * dim;
  ws->d_mlp_out.Resize(outputs);
  ScaleColumnsKernel(outputs, dim, scales_.data(), d_out,
                     ws->d_mlp_out.data());
  const bool need_features = grads.triplane != nullptr || d_x != nullptr;
  // d_features spans the whole MLP input; the extra inputs' part is unused.
  if (need_features) {
    ws->d_features.Resize(static_cast<size_t>(n) * in_dim);
    ws->d_features.Zero();
  }
  mlp_.Backward(p.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (!need_features) return;
  triplane_.Backward(p.triplane, n, ws->x, ws->d_features.data(),
                     grads.triplane, d_x, in_dim);
}

}  // namespace cuda
}  // namespace es
