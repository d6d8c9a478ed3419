#include "solvers/eval/static_eval.h"

#include <cmath>
#include <limits>

#include "core/metrics/image_metrics.h"
#include "core/render/dynamic_probability_view.h"
#include "solvers/eval/held_out_means.h"

namespace es {

StaticMetrics EvaluateStatic(const GaussianSet& g,
                             const std::vector<Frame>& frames,
                             const std::vector<int>& indices,
                             const RenderOptions& options) {
  std::vector<double> probability;
  const SplatView view = DynamicProbabilityView(g, &probability);

  Rasterizer rasterizer;
  RenderResult render;
  HeldOutMeans means;
  FiniteMean ssim_static;
  double tp = 0, fp = 0, fn = 0;
  bool any_mask = false;
  for (int index : indices) {
    const Frame& f = frames[index];
    rasterizer.Forward(f.camera, view, options, &render);
    const cv::Mat x(render.height, render.width, CV_64FC3, render.rgb.data());
    cv::Mat y;
    f.image.convertTo(y, CV_64F);
    means.Add(x, y, f.mask);
    if (f.mask.empty()) continue;
    any_mask = true;
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
  means.WriteTo(static_cast<int>(indices.size()), &out);
  out.ssim_static = ssim_static.Get();
  out.mask_precision = any_mask && tp + fp > 0 ? tp / (tp + fp) : nan;
  out.mask_recall = any_mask && tp + fn > 0 ? tp / (tp + fn) : nan;
  return out;
}

}  // namespace es
