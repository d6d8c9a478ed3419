#include "core/fields/motion_field.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/base/stage_profile.h"

namespace es {

void Grow(size_t size, std::vector<double>* buffer) {
  if (buffer->size() < size) buffer->resize(size);
}

MotionField::MotionField(const MotionFieldOptions& options)
    : options_(options),
      triplane_(options.triplane),
      mlp_(triplane_.output_dim(), options.mlp_width, options.mlp_depth, 3),
      triplane_params_(triplane_.num_params()),
      mlp_params_(mlp_.num_params()) {
  Initialize(options_.seed);
}

void MotionField::SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  triplane_.SetBox(lo, hi);
}

void MotionField::Initialize(uint32_t seed) {
  triplane_.Initialize(seed, triplane_params_.data());
  mlp_.Initialize(seed + 1, options_.last_layer_init_scale, mlp_params_.data());
}

double MotionField::box_diagonal() const {
  return (triplane_.box_max() - triplane_.box_min()).norm();
}

double MotionField::output_scale() const {
  return options_.velocity_scale * box_diagonal() * displacement_factor_;
}

FieldParams MotionField::params() const {
  return {triplane_params_.data(), mlp_params_.data()};
}

void MotionField::Evaluate(const FieldParams& p, int n, const double* x,
                           double* v, FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsForward);
  ws->batch = n;
  ws->x = x;
  Grow(static_cast<size_t>(n) * triplane_.output_dim(), &ws->features);
  triplane_.Sample(p.triplane, n, x, ws->features.data());
  mlp_.Forward(p.mlp, n, ws->features.data(), v, &ws->mlp);
  const double scale = output_scale();
  for (int i = 0; i < 3 * n; ++i) v[i] *= scale;
}

void MotionField::Backward(const FieldParams& p, const double* d_v,
                           const FieldGradients& grads, double* d_x,
                           FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsBackward);
  const int n = ws->batch;
  CHECK(ws->x != nullptr) << "MotionField::Backward before Evaluate";
  Grow(3 * static_cast<size_t>(n), &ws->d_mlp_out);
  const double scale = output_scale();
  for (int i = 0; i < 3 * n; ++i) ws->d_mlp_out[i] = d_v[i] * scale;
  const bool need_features = grads.triplane != nullptr || d_x != nullptr;
  if (need_features) {
    const size_t size = static_cast<size_t>(n) * triplane_.output_dim();
    Grow(size, &ws->d_features);
    std::fill(ws->d_features.begin(), ws->d_features.begin() + size, 0.0);
  }
  mlp_.Backward(p.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (need_features) {
    triplane_.Backward(p.triplane, n, ws->x, ws->d_features.data(),
                       grads.triplane, d_x, /*d_out_stride=*/0,
                       grads.triplane_chunks);
  }
}

}  // namespace es
