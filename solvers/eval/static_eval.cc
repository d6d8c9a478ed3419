#include "solvers/eval/static_eval.h"

#include <cmath>
#include <limits>

#include "core/metrics/image_metrics.h"
#include "solvers/eval/finite_mean.h"

namespace es {

StaticMetrics EvaluateStatic(const GaussianSet& g,
                             const std::vector<Frame>& frames,
                             const std::vector<int>& indices,
                             const RenderOptions& options) {
  std::vector<double> probability(g.size());
  for (int i = 0; i < g.size(); ++i)
    probability[i] = Sigmoid(g.dynamic_logits[i]);
  SplatView view = SplatView::Of(g);
  view.num_extra = 1;
  view.extra = probability.data();

  Rasterizer rasterizer;
  RenderResult render;
  FiniteMean psnr, ssim, psnr_water, ssim_water, psnr_static, ssim_static;
  double tp = 0, fp = 0, fn = 0;
  bool any_mask = false;
  for (int index : indices) {
    const Frame& f = frames[index];
    rasterizer.Forward(f.camera, view, options, &render);
    const cv::Mat x(render.height, render.width, CV_64FC3, render.rgb.data());
    cv::Mat y;
    f.image.convertTo(y, CV_64F);
    psnr.Add(Psnr(x, y));
    ssim.Add(Ssim(x, y));
    if (f.mask.empty()) continue;
    any_mask = true;
    psnr_water.Add(MaskedPsnr(x, y, f.mask));
    ssim_water.Add(MaskedSsim(x, y, f.mask));
    psnr_static.Add(MaskedPsnr(x, y, f.mask, /*invert=*/true));
    ssim_static.Add(MaskedSsim(x, y, f.mask, /*invert=*/true));
    cv::Mat m;
    f.mask.convertTo(m, CV_64F);
    for (int i = 0; i < render.height; ++i)
      for (int j = 0; j < render.width; ++j) {
        const bool predicted = render.extra[i * render.width + j] > 0.5;
        const bool water = m.at<double>(i, j) > 0.5;
        tp += predicted && water;
        fp += predicted && !water;
        fn += !predicted && water;
      }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  StaticMetrics out;
  out.frames = static_cast<int>(indices.size());
  out.psnr = psnr.Get();
  out.ssim = ssim.Get();
  out.psnr_water = psnr_water.Get();
  out.ssim_water = ssim_water.Get();
  out.psnr_static = psnr_static.Get();
  out.ssim_static = ssim_static.Get();
  out.mask_precision = any_mask && tp + fp > 0 ? tp / (tp + fp) : nan;
  out.mask_recall = any_mask && tp + fn > 0 ? tp / (tp + fn) : nan;
  return out;
}

}  // namespace es
