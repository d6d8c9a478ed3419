#ifndef EULERSPLAT_COSTS_MASK_BCE_LOSS_H_
#define EULERSPLAT_COSTS_MASK_BCE_LOSS_H_

#include <opencv2/core.hpp>

#include "costs/mask_bce_terms.h"

namespace es {

// The image-space part of the mask term; the Ceres cost that renders the
// dynamic probability channel is SplatRenderCost
// (costs/splat_render_cost.h, CreateMaskBceCost).
//
// Binary cross-entropy of a rendered per-pixel water probability (H x W
// doubles, row-major) against a mask (CV_32FC1 or CV_64FC1 in [0, 1], 1 =
// water), averaged over pixels. If d_probability is not null it receives
// `scale` * dl/d probability.
double MaskBceLoss(const double* probability, const cv::Mat& mask, double scale,
                   double* d_probability);

}  // namespace es

#endif  // EULERSPLAT_COSTS_MASK_BCE_LOSS_H_
