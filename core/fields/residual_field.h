#ifndef EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/fields/mlp.h"
#include "core/fields/motion_field.h"
#include "core/fields/triplane.h"

namespace es {

// Layout of one residual row: position offset, opacity logit offset, SH
// color offset (16 coefficients x rgb, [k][rgb] as in GaussianSet::sh).
constexpr int kResidualPosition = 0;
constexpr int kResidualOpacity = 3;
constexpr int kResidualSh = 4;
constexpr int kResidualDim = 52;

struct ResidualFieldOptions {
  ResidualFieldOptions() { triplane.channels = 16; }
  TriplaneOptions triplane;  // defaults: 128^2 x 16, product
  // Cycle index t is encoded with periods L, L/2, ... (t_frequencies of
  // them); cycle number p with periods 2 max_cycles, max_cycles, ... so p is
  // unambiguous over |p| < max_cycles.
  int cycle_length = 15;
  int t_frequencies = 4;
  int p_frequencies = 4;
  int max_cycles = 16;
  int mlp_width = 128;
  int mlp_depth = 2;
  // Position offsets are MLP outputs times position_scale * box diagonal
  // (scale-free like the motion field); opacity and SH offsets are unscaled.
  double position_scale = 0.01;
  double last_layer_init_scale = 0.01;
  uint32_t seed = 2;
};

// The non-periodic residual field D(x0, t, p) -> R^52 from the canonical
// position x0, cycle index t and cycle number p. MLP input: triplane(x0),
// then the encoding of t, then that of p.
class ResidualField {
 public:
  explicit ResidualField(const ResidualFieldOptions& options);

  void SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  void Initialize(uint32_t seed);

  const ResidualFieldOptions& options() const { return options_; }
  const Triplane& triplane() const { return triplane_; }
  const Mlp& mlp() const { return mlp_; }
  int encoding_dim() const;

  std::vector<double>& triplane_params() { return triplane_params_; }
  std::vector<double>& mlp_params() { return mlp_params_; }
  FieldParams params() const;

  // out (n x kResidualDim) = D(x0 (n x 3), t (n), p (n)).
  void Evaluate(const FieldParams& params, int n, const double* x0,
                const int* t, const int* p, double* out,
                FieldWorkspace* ws) const;
  // Backward of the last Evaluate on *ws: given d_out (n x kResidualDim),
  // accumulates parameter gradients and dL/dx0 (n x 3, nullable).
  void Backward(const FieldParams& params, const double* d_out,
                const FieldGradients& grads, double* d_x0,
                FieldWorkspace* ws) const;

 private:
  ResidualFieldOptions options_;
  Triplane triplane_;
  Mlp mlp_;
  Eigen::Matrix<double, kResidualDim, 1> output_scale_;
  std::vector<double> triplane_params_, mlp_params_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_
