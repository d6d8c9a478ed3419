#ifndef EULERSPLAT_SOLVERS_EVAL_HELD_OUT_MEANS_H_
#define EULERSPLAT_SOLVERS_EVAL_HELD_OUT_MEANS_H_

#include <cmath>

#include <opencv2/core.hpp>

#include "core/metrics/image_metrics.h"
#include "solvers/eval/finite_mean.h"

namespace es {

// The scenery "far from the water": farther from every water pixel than
// this fraction of the image diagonal (twice the realism figures' water
// margin). Stochastic water reaches past its mask (spray below the
// mask's threshold, a droplet's blur), and there a model that moves the
// water like the input loses PSNR as another draw of the same water
// does; out here the scenery is the scenery alone, and Stage 3 should
// leave it as Stage 1 fit it (docs/results/stage3-start.md).
constexpr double kFarSceneryDiagonals = 0.04;

// The image figures both held-out evaluations (static_eval.h,
// loop_evaluation.h) report, as means over frames: PSNR and SSIM of the
// whole image and, on frames with a mask (> 0.5 is water), of the water,
// and PSNR of the rest and of the scenery far from the water.
struct HeldOutMeans {
  // `render` and `truth` are CV_64FC3; `mask` may be empty.
  void Add(const cv::Mat& render, const cv::Mat& truth, const cv::Mat& mask) {
    psnr.Add(Psnr(render, truth));
    ssim.Add(Ssim(render, truth));
    if (mask.empty()) return;
    psnr_water.Add(MaskedPsnr(render, truth, mask));
    ssim_water.Add(MaskedSsim(render, truth, mask));
    psnr_static.Add(MaskedPsnr(render, truth, mask, /*invert=*/true));
    psnr_far_scenery.Add(MaskedPsnr(
        render, truth,
        FarFromMask(mask, kFarSceneryDiagonals * std::hypot(mask.cols,
                                                             mask.rows))));
  }

  // Sets the fields StaticMetrics and LoopMetrics share: `frames` and the
  // means.
  template <typename Metrics>
  void WriteTo(int frames, Metrics* out) const {
    out->frames = frames;
    out->psnr = psnr.Get();
    out->ssim = ssim.Get();
    out->psnr_water = psnr_water.Get();
    out->ssim_water = ssim_water.Get();
    out->psnr_static = psnr_static.Get();
    out->psnr_far_scenery = psnr_far_scenery.Get();
  }

  FiniteMean psnr, ssim, psnr_water, ssim_water, psnr_static,
      psnr_far_scenery;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_HELD_OUT_MEANS_H_
