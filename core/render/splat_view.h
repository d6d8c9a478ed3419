#ifndef EULERSPLAT_CORE_RENDER_SPLAT_VIEW_H_
#define EULERSPLAT_CORE_RENDER_SPLAT_VIEW_H_

// What the rasterizer reads of the splats and what its backward pass writes
// for them; shared by the rasterizer and its projection.

#include <vector>

#include "core/model/gaussians.h"

namespace es {

// Read-only views of the splat attributes to render (layouts as in
// GaussianSet). `means` may point at advected positions rather than the
// canonical ones.
struct SplatView {
  int count = 0;
  int sh_degree = 0;
  const double* means = nullptr;           // 3N
  const double* log_scales = nullptr;      // 3N
  const double* quats = nullptr;           // 4N, w x y z
  const double* opacity_logits = nullptr;  // N
  const double* sh = nullptr;              // 3KN, [n][k][rgb]
  int num_extra = 0;                       // extra channels per Gaussian
  const double* extra = nullptr;           // N * num_extra, [n][e]

  // All attributes of g, no extra channels.
  static SplatView Of(const GaussianSet& g);
};

// Gradients with respect to the SplatView arrays (same sizes and layouts).
struct SplatGradients {
  std::vector<double> means, log_scales, quats, opacity_logits, sh, extra;
  void Resize(int count, int sh_degree, int num_extra);
};

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_SPLAT_VIEW_H_
