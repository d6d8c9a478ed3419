#include "core/fields/residual_field.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/fields/positional_encoding.h"
#include "core/base/stage_profile.h"

namespace es {

ResidualField::ResidualField(const ResidualFieldOptions& options)
    : options_(options),
      triplane_(options.triplane),
      mlp_(triplane_.output_dim() + 2 * options.t_frequencies +
               2 * options.p_frequencies,
           options.mlp_width, options.mlp_depth, kResidualDim),
      triplane_params_(triplane_.num_params()),
      mlp_params_(mlp_.num_params()) {
  CHECK_GE(options_.cycle_length, 1);
  CHECK_GE(options_.max_cycles, 1);
  SetBox(triplane_.box_min(), triplane_.box_max());
  Initialize(options_.seed);
}

void ResidualField::SetBox(const Eigen::Vector3d& lo,
                           const Eigen::Vector3d& hi) {
  triplane_.SetBox(lo, hi);
  output_scale_.setOnes();
  output_scale_.segment<3>(kResidualPosition)
      .setConstant(options_.position_scale * (hi - lo).norm());
}

void ResidualField::Initialize(uint32_t seed) {
  triplane_.Initialize(seed, triplane_params_.data());
  mlp_.Initialize(seed + 1, options_.last_layer_init_scale, mlp_params_.data());
}

int ResidualField::encoding_dim() const {
  return 2 * options_.t_frequencies + 2 * options_.p_frequencies;
}

FieldParams ResidualField::params() const {
  return {triplane_params_.data(), mlp_params_.data()};
}

void ResidualField::Evaluate(const FieldParams& params, int n, const double* x0,
                             const int* t, const int* p, double* out,
                             FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsForward);
  const int feature_dim = triplane_.output_dim();
  const int in_dim = mlp_.input_dim();
  ws->batch = n;
  ws->x = x0;
  Grow(static_cast<size_t>(n) * in_dim, &ws->features);
  triplane_.Sample(params.triplane, n, x0, ws->features.data(), in_dim);
  const double p_period = 2.0 * options_.max_cycles;
  for (int i = 0; i < n; ++i) {
    double* row = ws->features.data() + i * in_dim + feature_dim;
    EncodeSinusoidal(t[i], options_.t_frequencies, options_.cycle_length, row);
    EncodeSinusoidal(p[i], options_.p_frequencies, p_period,
                     row + 2 * options_.t_frequencies);
  }
  mlp_.Forward(params.mlp, n, ws->features.data(), out, &ws->mlp);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < kResidualDim; ++j)
      out[i * kResidualDim + j] *= output_scale_[j];
  }
}

void ResidualField::Backward(const FieldParams& params, const double* d_out,
                             const FieldGradients& grads, double* d_x0,
                             FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsBackward);
  const int n = ws->batch;
  CHECK(ws->x != nullptr) << "ResidualField::Backward before Evaluate";
  Grow(static_cast<size_t>(n) * kResidualDim, &ws->d_mlp_out);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < kResidualDim; ++j) {
      ws->d_mlp_out[i * kResidualDim + j] =
          d_out[i * kResidualDim + j] * output_scale_[j];
    }
  }
  const bool need_features = grads.triplane != nullptr || d_x0 != nullptr;
  // d_features spans the whole MLP input; the encodings' part is unused.
  if (need_features) {
    const size_t size = static_cast<size_t>(n) * mlp_.input_dim();
    Grow(size, &ws->d_features);
    std::fill(ws->d_features.begin(), ws->d_features.begin() + size, 0.0);
  }
  mlp_.Backward(params.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (!need_features) return;
  triplane_.Backward(params.triplane, n, ws->x, ws->d_features.data(),
                     grads.triplane, d_x0, mlp_.input_dim(),
                     grads.triplane_chunks);
}

}  // namespace es
