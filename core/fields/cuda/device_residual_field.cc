#include "core/fields/cuda/device_residual_field.h"

#include <vector>

#include <glog/logging.h>

#include "core/fields/cuda/field_kernels.h"

namespace es {
namespace cuda {

DeviceResidualField::DeviceResidualField(const ResidualField& field)
    : triplane_(field.triplane()),
      mlp_(field.mlp()),
      options_(field.options()) {
  // ResidualField::SetBox's scales: positions follow the box diagonal.
  std::vector<double> scales(kResidualDim, 1.0);
  const double position =
      options_.position_scale *
      (field.triplane().box_max() - field.triplane().box_min()).norm();
  for (int j = 0; j < 3; ++j) scales[kResidualPosition + j] = position;
  scales_.Upload(scales);
}

void DeviceResidualField::Evaluate(const FieldParams& params, int n,
                                   const double* x0, const int* t,
                                   const int* p, double* out,
                                   DeviceFieldWorkspace* ws) const {
  const int in_dim = mlp_.input_dim();
  ws->batch = n;
  ws->x = x0;
  ws->features.Resize(static_cast<size_t>(n) * in_dim);
  triplane_.Sample(params.triplane, n, x0, ws->features.data(), in_dim);
  EncodeCycleKernel(n, t, p, options_.t_frequencies, options_.cycle_length,
                    options_.p_frequencies, 2.0 * options_.max_cycles,
                    ws->features.data(), in_dim, triplane_.output_dim());
  mlp_.Forward(params.mlp, n, ws->features.data(), out, &ws->mlp);
  ScaleColumnsKernel(static_cast<long long>(n) * kResidualDim, kResidualDim,
                     scales_.data(), out, out);
}

void DeviceResidualField::Backward(const FieldParams& params,
                                   const double* d_out,
                                   const FieldGradients& grads, double* d_x0,
                                   DeviceFieldWorkspace* ws) const {
  CHECK(ws->x != nullptr) << "DeviceResidualField::Backward before Evaluate";
  CHECK(grads.triplane_chunks == nullptr)
      << "the device triplane gradient is dense: no chunk flags";
  const int n = ws->batch;
  const long long outputs = static_cast<long long>(n) * kResidualDim;
  ws->d_mlp_out.Resize(outputs);
  ScaleColumnsKernel(outputs, kResidualDim, scales_.data(), d_out,
                     ws->d_mlp_out.data());
  const bool need_features = grads.triplane != nullptr || d_x0 != nullptr;
  // d_features spans the whole MLP input; the encodings' part is unused.
  if (need_features) {
    ws->d_features.Resize(static_cast<size_t>(n) * mlp_.input_dim());
    ws->d_features.Zero();
  }
  mlp_.Backward(params.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (!need_features) return;
  triplane_.Backward(params.triplane, n, ws->x, ws->d_features.data(),
                     grads.triplane, d_x0, mlp_.input_dim());
}

}  // namespace cuda
}  // namespace es
