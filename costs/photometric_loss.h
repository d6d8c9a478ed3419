#ifndef EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_
#define EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_

#include <opencv2/core.hpp>

namespace es {

// The image-space part of the photometric term; the Ceres cost that renders
// and differentiates through the rasterizer is SplatRenderCost
// (costs/splat_render_cost.h, CreatePhotometricCost).
//
// The 3DGS photometric loss of a rendered H x W x 3 image (row-major
// doubles) against a target (CV_32FC3 or CV_64FC3, same size):
//   l = (1 - ssim_weight) L1 + ssim_weight (1 - SSIM),
// both means over pixels and channels (SSIM as in core/metrics/image_metrics.h).
// If d_rendered is not null it receives `scale` * dl/d rendered.
double PhotometricLoss(const double* rendered, const cv::Mat& target,
                       double ssim_weight, double scale, double* d_rendered);

}  // namespace es

#endif  // EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_
