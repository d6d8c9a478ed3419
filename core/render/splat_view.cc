#include "core/render/splat_view.h"

namespace es {

SplatView SplatView::Of(const GaussianSet& g) {
  SplatView v;
  v.count = g.size();
  v.sh_degree = g.sh_degree;
  v.means = g.means.data();
  v.log_scales = g.log_scales.data();
  v.quats = g.quats.data();
  v.opacity_logits = g.opacity_logits.data();
  v.sh = g.sh.data();
  return v;
}

void SplatGradients::Resize(int count, int sh_degree, int num_extra) {
  means.assign(3 * count, 0.0);
  log_scales.assign(3 * count, 0.0);
  quats.assign(4 * count, 0.0);
  opacity_logits.assign(count, 0.0);
  sh.assign(3 * NumShCoeffs(sh_degree) * count, 0.0);
  extra.assign(static_cast<size_t>(num_extra) * count, 0.0);
}

}  // namespace es
