#include "solvers/eval/realism_evaluation.h"

#include <glog/logging.h>

#include "core/loop/loop_renderer.h"

namespace es {

std::vector<cv::Mat> RenderAtInputCameras(const LoopModel& model,
                                          const std::vector<Frame>& frames,
                                          const RenderOptions& options) {
  LoopRenderer renderer(&model, options);
  std::vector<cv::Mat> out;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (i == 0) {
      renderer.Start(0);
    } else {
      renderer.Advance();
    }
    const RenderResult& r = renderer.Render(frames[i].camera);
    out.push_back(cv::Mat(r.height, r.width, CV_64FC3,
                          const_cast<double*>(r.rgb.data()))
                      .clone());
  }
  return out;
}

RealismMetrics EvaluateRealism(const LoopModel& model,
                               const std::vector<Frame>& frames,
                               const RenderOptions& options,
                               const RealismOptions& realism) {
  CHECK_GE(frames.size(), 2u);
  std::vector<cv::Mat> real, masks;
  bool has_masks = true;
  for (const Frame& f : frames) {
    real.push_back(f.image);
    masks.push_back(f.mask);
    has_masks = has_masks && !f.mask.empty();
  }
  if (!has_masks) masks.clear();
  return ComputeRealism(RenderAtInputCameras(model, frames, options), real,
                        masks, realism);
}

}  // namespace es
