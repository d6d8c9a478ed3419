#include "core/fields/residual_field.h"

#include <glog/logging.h>

#include "core/fields/positional_encoding.h"
#include "core/base/stage_profile.h"

namespace es {
namespace {

// The MLP inputs after the triplane features: the encodings of t and p.
int EncodingDim(const ResidualFieldOptions& o) {
  return 2 * o.t_frequencies + 2 * o.p_frequencies;
}

}  // namespace

ResidualField::ResidualField(const ResidualFieldOptions& options)
    : TriplaneMlpField("ResidualField", options.triplane,
                       EncodingDim(options),
                       options.mlp_width, options.mlp_depth,
                       options.last_layer_init_scale, options.seed),
      options_(options) {
  CHECK_GE(options_.cycle_length, 1);
  CHECK_GE(options_.max_cycles, 1);
  SetBox(triplane().box_min(), triplane().box_max());
}

// Position offsets follow the box diagonal; the others stay unscaled (1).
void ResidualField::SetBox(const Eigen::Vector3d& lo,
                           const Eigen::Vector3d& hi) {
  SetTriplaneBox(lo, hi);
  SetOutputScales(kResidualPosition, 3,
                  options_.position_scale * box_diagonal());
}

int ResidualField::encoding_dim() const { return EncodingDim(options_); }

void ResidualField::Evaluate(const FieldParams& params, int n, const double* x0,
                             const int* t, const int* p, double* out,
                             FieldWorkspace* ws) const {
  ScopedStage timer(Stage::kFieldsForward);
  SampleFeatures(params, n, x0, ws);
  const int feature_dim = triplane().output_dim();
  const int in_dim = mlp().input_dim();
  const double p_period = 2.0 * options_.max_cycles;
  for (int i = 0; i < n; ++i) {
    double* row = ws->features.data() + i * in_dim + feature_dim;
    EncodeSinusoidal(t[i], options_.t_frequencies, options_.cycle_length, row);
    EncodeSinusoidal(p[i], options_.p_frequencies, p_period,
                     row + 2 * options_.t_frequencies);
  }
  ForwardScaled(params, out, ws);
}

}  // namespace es
