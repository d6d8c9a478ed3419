#include "core/fields/cuda/device_mlp.h"

#include <glog/logging.h>

#include "core/fields/cuda/field_kernels.h"

namespace es {
namespace cuda {

DeviceMlp::DeviceMlp(const Mlp& mlp)
    : input_dim_(mlp.input_dim()),
      width_(mlp.width()),
      depth_(mlp.depth()),
      output_dim_(mlp.output_dim()) {
  offsets_.push_back(0);
  for (int l = 0; l <= depth_; ++l) {
    offsets_.push_back(offsets_.back() + layer_out(l) * (layer_in(l) + 1));
  }
  CHECK_EQ(num_params(), mlp.num_params());
}

void DeviceMlp::Forward(const double* params, int n, const double* input,
                        double* out, DeviceMlpWorkspace* ws) const {
  CHECK_GE(n, 0);
  ws->batch = n;
  ws->input = input;
  ws->hidden.resize(depth_);
  for (DeviceBuffer<double>& h : ws->hidden) {
    h.Resize(static_cast<size_t>(n) * width_);
  }
  for (int l = 0; l <= depth_; ++l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* w = params + offsets_[l];
    const double* a = l == 0 ? input : ws->hidden[l - 1].data();
    double* y = l == depth_ ? out : ws->hidden[l].data();
    LayerForwardKernel(n, in, o, a, w, w + o * in, /*relu=*/l < depth_, y);
  }
}

void DeviceMlp::Backward(const double* params, const double* d_out,
                         double* d_params, double* d_input,
                         DeviceMlpWorkspace* ws) const {
  CHECK(ws->input != nullptr) << "DeviceMlp::Backward before Forward";
  const int n = ws->batch;
  if (depth_ > 0) {
    ws->grad.Resize(static_cast<size_t>(n) * width_);
    ws->grad_prev.Resize(static_cast<size_t>(n) * width_);
  }
  // Layer by layer from the output; `g` is dL/d(layer output), written into
  // grad and grad_prev alternately.
  const double* g = d_out;
  DeviceBuffer<double>* buffers[2] = {&ws->grad, &ws->grad_prev};
  for (int l = depth_; l >= 0; --l) {
    const int in = layer_in(l), o = layer_out(l);
    const double* w = params + offsets_[l];
    const double* a = l == 0 ? ws->input : ws->hidden[l - 1].data();
    if (d_params != nullptr) {
      double* dw = d_params + offsets_[l];
      LayerWeightGradientKernel(n, in, o, g, a, dw, dw + o * in);
    }
    if (l == 0) {
      if (d_input != nullptr) {
        LayerInputGradientKernel(n, o, in, g, w, nullptr,
                                 /*accumulate=*/true, d_input);
      }
      break;
    }
    // Through the previous layer's ReLU: zero where it was inactive.
    double* next = buffers[l % 2]->data();
    LayerInputGradientKernel(n, o, in, g, w, a, /*accumulate=*/false, next);
    g = next;
  }
}

}  // namespace cuda
}  // namespace es
