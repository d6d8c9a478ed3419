#include "core/fields/cuda/device_motion_field.h"

#include <glog/logging.h>

#include "core/fields/cuda/field_kernels.h"

namespace es {
namespace cuda {

DeviceMotionField::DeviceMotionField(const MotionField& field)
    : triplane_(field.triplane()),
      mlp_(field.mlp()),
      box_diagonal_(field.box_diagonal()),
      output_scale_(field.output_scale()) {
  const double scales[3] = {output_scale_, output_scale_, output_scale_};
  scales_.Upload(scales, 3);
}

void DeviceMotionField::Evaluate(const FieldParams& p, int n, const double* x,
                                 double* v, DeviceFieldWorkspace* ws) const {
  ws->batch = n;
  ws->x = x;
  ws->features.Resize(static_cast<size_t>(n) * triplane_.output_dim());
  triplane_.Sample(p.triplane, n, x, ws->features.data());
  mlp_.Forward(p.mlp, n, ws->features.data(), v, &ws->mlp);
  ScaleColumnsKernel(3LL * n, 3, scales_.data(), v, v);
}

void DeviceMotionField::Backward(const FieldParams& p, const double* d_v,
                                 const FieldGradients& grads, double* d_x,
                                 DeviceFieldWorkspace* ws) const {
  CHECK(ws->x != nullptr) << "DeviceMotionField::Backward before Evaluate";
  CHECK(grads.triplane_chunks == nullptr)
      << "the device triplane gradient is dense: no chunk flags";
  const int n = ws->batch;
  ws->d_mlp_out.Resize(3 * static_cast<size_t>(n));
  ScaleColumnsKernel(3LL * n, 3, scales_.data(), d_v, ws->d_mlp_out.data());
  const bool need_features = grads.triplane != nullptr || d_x != nullptr;
  if (need_features) {
    ws->d_features.Resize(static_cast<size_t>(n) * triplane_.output_dim());
    ws->d_features.Zero();
  }
  mlp_.Backward(p.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (need_features) {
    triplane_.Backward(p.triplane, n, ws->x, ws->d_features.data(),
                       grads.triplane, d_x);
  }
}

}  // namespace cuda
}  // namespace es
