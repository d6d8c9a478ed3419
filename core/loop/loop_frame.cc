#include "core/loop/loop_frame.h"

#include <glog/logging.h>

#include "core/loop/loop_renderer.h"

namespace es {

GaussianSet CopySplats(const SplatView& view, const GaussianSet& canonical) {
  CHECK_EQ(view.count, canonical.size());
  GaussianSet g;
  g.sh_degree = view.sh_degree;
  g.Resize(view.count);
  const size_t n = view.count;
  g.means.assign(view.means, view.means + 3 * n);
  g.log_scales.assign(view.log_scales, view.log_scales + 3 * n);
  g.quats.assign(view.quats, view.quats + 4 * n);
  g.opacity_logits.assign(view.opacity_logits, view.opacity_logits + n);
  g.sh.assign(view.sh, view.sh + 3 * g.sh_coeffs() * n);
  g.dynamic_logits = canonical.dynamic_logits;
  return g;
}

GaussianSet LoopFrameSplats(const LoopModel& model, int frame) {
  CHECK_GE(frame, 0);
  LoopRenderer player(&model, RenderOptions());
  player.Start(frame);
  return CopySplats(player.Compose(), model.gaussians);
}

}  // namespace es
