#ifndef EULERSPLAT_CORE_FIELDS_TRIPLANE_MLP_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_TRIPLANE_MLP_FIELD_H_

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <glog/logging.h>

#include "core/base/stage_profile.h"
#include "core/fields/mlp.h"
#include "core/fields/triplane.h"

namespace es {

// Read-only parameter pointers (Ceres blocks) a field is evaluated with; the
// field's own storage or, e.g., the arrays Ceres hands a cost function.
struct FieldParams {
  const double* triplane = nullptr;  // Triplane::num_params()
  const double* mlp = nullptr;       // Mlp::num_params()
};

// Gradient accumulators (+=); nullptr skips that block.
struct FieldGradients {
  double* triplane = nullptr;
  double* mlp = nullptr;
  // Nullable: one flag per chunk of the triplane gradient
  // (core/fields/gradient_chunks.h), set where Backward writes.
  char* triplane_chunks = nullptr;
};

// State of one Evaluate kept for Backward, row-major arrays; buffers only
// grow, so no allocation after the first call at the largest batch.
struct FieldWorkspace {
  int batch = 0;
  const double* x = nullptr;     // not owned; must outlive Backward
  std::vector<double> features;  // MLP input, batch x its input dim
  std::vector<double> d_features;
  std::vector<double> d_mlp_out;
  MlpWorkspace mlp;
};

// What the fields V and D are: out = MLP(triplane(x), extra inputs), each
// of the kOutputs output columns times its output scale. A derived field
// evaluates with SampleFeatures, fills its extra input columns (if any),
// then ForwardScaled, and keeps its output scales current; Backward is
// shared.
template <int kOutputs>
class TriplaneMlpField {
 public:
  using OutputScales = Eigen::Matrix<double, kOutputs, 1>;

  const Triplane& triplane() const { return triplane_; }
  const Mlp& mlp() const { return mlp_; }
  // The MLP's arithmetic (Mlp::set_precision); double unless set.
  void set_mlp_precision(MlpPrecision precision) {
    mlp_.set_precision(precision);
  }
  double box_diagonal() const {
    return (triplane_.box_max() - triplane_.box_min()).norm();
  }
  // What each output column is multiplied by.
  const OutputScales& output_scales() const { return output_scales_; }

  std::vector<double>& triplane_params() { return triplane_params_; }
  std::vector<double>& mlp_params() { return mlp_params_; }
  FieldParams params() const {
    return {triplane_params_.data(), mlp_params_.data()};
  }

  // Re-draws the parameters from `seed`: the triplane's from seed, the MLP's
  // from seed + 1 with the last layer init scale.
  void Initialize(uint32_t seed) {
    triplane_.Initialize(seed, triplane_params_.data());
    mlp_.Initialize(seed + 1, last_layer_init_scale_, mlp_params_.data());
  }

  // Backward of the last Evaluate on *ws: given d_out (n x kOutputs),
  // accumulates parameter gradients into grads and dL/dx into d_x (n x 3,
  // nullable).
  void Backward(const FieldParams& p, const double* d_out,
                const FieldGradients& grads, double* d_x,
                FieldWorkspace* ws) const;

 protected:
  // The MLP reads the triplane features then `extra_inputs` more columns;
  // the output scales start at 1. `name` (a literal, the derived class's)
  // starts the CHECK messages. Initializes the parameters from `seed`.
  TriplaneMlpField(const char* name, const TriplaneOptions& triplane,
                   int extra_inputs, int mlp_width, int mlp_depth,
                   double last_layer_init_scale, uint32_t seed)
      : name_(name),
        triplane_(triplane),
        mlp_(triplane_.output_dim() + extra_inputs, mlp_width, mlp_depth,
             kOutputs),
        last_layer_init_scale_(last_layer_init_scale),
        triplane_params_(triplane_.num_params()),
        mlp_params_(mlp_.num_params()) {
    Initialize(seed);
  }

  // Sets the box the triplane spans (parameters are kept); the derived
  // field then updates the output scales that follow it.
  void SetTriplaneBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    triplane_.SetBox(lo, hi);
  }
  // Output scales [first, first + count) become `scale`.
  void SetOutputScales(int first, int count, double scale) {
    output_scales_.segment(first, count).setConstant(scale);
  }

  // Evaluate's first half: keeps x (n x 3) for Backward and samples
  // triplane(x) into the leading columns of ws->features (n x
  // mlp().input_dim()); the derived field fills the other columns.
  void SampleFeatures(const FieldParams& p, int n, const double* x,
                      FieldWorkspace* ws) const;
  // Evaluate's second half: out (n x kOutputs) = MLP(features), each column
  // times its output scale.
  void ForwardScaled(const FieldParams& p, double* out,
                     FieldWorkspace* ws) const;

 private:
  // Resizes *buffer to at least `size` values, never shrinking it.
  static void Grow(size_t size, std::vector<double>* buffer) {
    if (buffer->size() < size) buffer->resize(size);
  }

  const char* name_;
  Triplane triplane_;
  Mlp mlp_;
  double last_layer_init_scale_;
  std::vector<double> triplane_params_, mlp_params_;
  OutputScales output_scales_ = OutputScales::Ones();
};

template <int kOutputs>
void TriplaneMlpField<kOutputs>::SampleFeatures(const FieldParams& p, int n,
                                                const double* x,
                                                FieldWorkspace* ws) const {
  const int in_dim = mlp_.input_dim();
  ws->batch = n;
  ws->x = x;
  Grow(static_cast<size_t>(n) * in_dim, &ws->features);
  triplane_.Sample(p.triplane, n, x, ws->features.data(), in_dim);
}

template <int kOutputs>
void TriplaneMlpField<kOutputs>::ForwardScaled(const FieldParams& p,
                                               double* out,
                                               FieldWorkspace* ws) const {
  const int n = ws->batch;
  mlp_.Forward(p.mlp, n, ws->features.data(), out, &ws->mlp);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < kOutputs; ++j)
      out[i * kOutputs + j] *= output_scales_[j];
  }
}

template <int kOutputs>
void TriplaneMlpField<kOutputs>::Backward(const FieldParams& p,
                                          const double* d_out,
                                          const FieldGradients& grads,
                                          double* d_x,
                                          FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsBackward);
  const int n = ws->batch;
  const int in_dim = mlp_.input_dim();
  CHECK(ws->x != nullptr) << name_ << "::Backward before Evaluate";
  Grow(static_cast<size_t>(n) * kOutputs, &ws->d_mlp_out);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < kOutputs; ++j) {
      ws->d_mlp_out[i * kOutputs + j] =
          d_out[i * kOutputs + j] * output_scales_[j];
    }
  }
  const bool need_features = grads.triplane != nullptr || d_x != nullptr;
  // d_features spans the whole MLP input; the extra inputs' part is unused.
  if (need_features) {
    const size_t size = static_cast<size_t>(n) * in_dim;
    Grow(size, &ws->d_features);
    std::fill(ws->d_features.begin(), ws->d_features.begin() + size, 0.0);
  }
  mlp_.Backward(p.mlp, ws->d_mlp_out.data(), grads.mlp,
                need_features ? ws->d_features.data() : nullptr, &ws->mlp);
  if (!need_features) return;
  triplane_.Backward(p.triplane, n, ws->x, ws->d_features.data(),
                     grads.triplane, d_x, in_dim, grads.triplane_chunks);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_TRIPLANE_MLP_FIELD_H_
