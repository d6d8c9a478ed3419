#include "costs/photometric_loss.h"

#include <glog/logging.h>

#include "core/metrics/image_metrics.h"
#include "core/profile/stage_profile.h"

namespace es {
namespace {

// The loss's full-image buffers, per calling thread and reused while the
// image size stays the same: a training loop calls this every iteration.
struct PhotometricWorkspace {
  cv::Mat target, d_l1, d_ssim;
  SsimWorkspace ssim;
};

PhotometricWorkspace& Workspace() {
  thread_local PhotometricWorkspace ws;
  return ws;
}

}  // namespace

double PhotometricLoss(const double* rendered, const cv::Mat& target,
                       double ssim_weight, double scale, double* d_rendered) {
  CHECK_EQ(target.channels(), 3);
  PhotometricWorkspace& ws = Workspace();
  const cv::Mat x(target.rows, target.cols, CV_64FC3,
                  const_cast<double*>(rendered));
  const cv::Mat* y = &target;
  if (target.depth() != CV_64F) {
    target.convertTo(ws.target, CV_64F);
    y = &ws.target;
  }
  cv::Mat* want_l1 = d_rendered ? &ws.d_l1 : nullptr;
  cv::Mat* want_ssim = d_rendered && ssim_weight != 0 ? &ws.d_ssim : nullptr;
  double l1 = 0, ssim = 1;
  {
    ScopedStage timer(Stage::kLossL1);
    l1 = L1Loss(x, *y, want_l1);
  }
  if (ssim_weight != 0) {
    ScopedStage timer(Stage::kLossSsim);
    ssim = Ssim(x, *y, want_ssim, &ws.ssim);
  }
  if (d_rendered) {
    const size_t n = x.total() * 3;
    const double* g1 = ws.d_l1.ptr<double>();
    const double a = scale * (1 - ssim_weight);
    if (want_ssim) {
      const double* g2 = ws.d_ssim.ptr<double>();
      const double b = -scale * ssim_weight;
      for (size_t i = 0; i < n; ++i) d_rendered[i] = a * g1[i] + b * g2[i];
    } else {
      for (size_t i = 0; i < n; ++i) d_rendered[i] = a * g1[i];
    }
  }
  return (1 - ssim_weight) * l1 + ssim_weight * (1 - ssim);
}

}  // namespace es
