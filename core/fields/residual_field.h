#ifndef EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_
#define EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_

#include <cstdint>

#include <Eigen/Core>

#include "core/fields/triplane_mlp_field.h"

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
class ResidualField : public TriplaneMlpField<kResidualDim> {
 public:
  explicit ResidualField(const ResidualFieldOptions& options);

  void SetBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

  const ResidualFieldOptions& options() const { return options_; }
  int encoding_dim() const;

  // out (n x kResidualDim) = D(x0 (n x 3), t (n), p (n)), keeping state in
  // *ws for Backward (inherited: given d_out (n x kResidualDim), accumulates
  // parameter gradients and dL/dx0).
  void Evaluate(const FieldParams& params, int n, const double* x0,
                const int* t, const int* p, double* out,
                FieldWorkspace* ws) const;

 private:
  ResidualFieldOptions options_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_RESIDUAL_FIELD_H_
