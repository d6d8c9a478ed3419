#ifndef EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_
#define EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_

#include <opencv2/core.hpp>

#include <cstddef>

#include "core/metrics/ssim.h"
#include "costs/ssim_target_cache.h"

namespace es {

// What the targets' SSIM statistics may keep by default: every frame of
// the default scene (0.5 MB each at 160x120), ~35 at 320x240 (1.8 MB). The
// cache saves about a fifth of the loss's time (under 1% of an iteration),
// so it is kept small next to the model's own memory.
constexpr size_t kDefaultSsimCacheBytes = size_t{64} << 20;

// The image-space part of the photometric term; the Ceres cost that renders
// and differentiates through the rasterizer is SplatRenderCost
// (costs/splat_render_cost.h, CreatePhotometricCost).
//
// The 3DGS photometric loss of a rendered H x W x 3 image (row-major
// doubles) against a target (CV_32FC3 or CV_64FC3, same size):
//   l = (1 - ssim_weight) L1 + ssim_weight (1 - SSIM),
// both means over pixels and channels (SSIM as in
// core/metrics/image_metrics.h). SSIM runs in float unless use_double (the
// gradient tests), with each target's window statistics kept in a cache of
// ssim_cache_bytes (targets must not change while they may be looked up).
// Keeps its buffers between calls: not thread-safe.
class PhotometricLoss {
 public:
  // level: SSIM's kernels (kAuto: the CPU's best).
  PhotometricLoss(double ssim_weight, bool use_double,
                  size_t ssim_cache_bytes = kDefaultSsimCacheBytes,
                  SimdLevel level = SimdLevel::kAuto);

  // The loss; if d_rendered is not null it receives scale * dl/d rendered.
  double Evaluate(const double* rendered, const cv::Mat& target, double scale,
                  double* d_rendered);

 private:
  template <typename T>
  double SsimAndL1(const double* rendered, const cv::Mat& target,
                   SsimTargetCache<T>* cache, SsimScratch<T>* scratch,
                   double ssim_grad_scale, double l1_grad_scale,
                   double* d_rendered, double* l1);

  double ssim_weight_;
  bool use_double_;
  SsimTargetCache<float> float_cache_;
  SsimTargetCache<double> double_cache_;
  SsimScratch<float> float_scratch_;
  SsimScratch<double> double_scratch_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_PHOTOMETRIC_LOSS_H_
