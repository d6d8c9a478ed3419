#ifndef EULERSPLAT_SOLVERS_EVAL_STATIC_EVAL_H_
#define EULERSPLAT_SOLVERS_EVAL_STATIC_EVAL_H_

#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"

namespace es {

// Held-out quality of a static model. Image metrics are means over frames;
// the water / static variants use the frames' masks (> 0.5 is water) and
// skip frames where the region is empty (NaN when no frame has one). Mask
// precision / recall compare the rendered dynamic channel > 0.5 with the
// mask > 0.5 over all held-out pixels (NaN without masks).
struct StaticMetrics {
  int frames = 0;
  double psnr = 0, ssim = 0;
  double psnr_water = 0, ssim_water = 0;
  double psnr_static = 0, ssim_static = 0;
  double psnr_far_scenery = 0;  // held_out_means.h's kFarSceneryDiagonals
  double mask_precision = 0, mask_recall = 0;
};

StaticMetrics EvaluateStatic(const GaussianSet& gaussians,
                             const std::vector<Frame>& frames,
                             const std::vector<int>& indices,
                             const RenderOptions& options);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_STATIC_EVAL_H_
