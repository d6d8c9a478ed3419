#include "costs/photometric_loss.h"

#include <glog/logging.h>

#include "core/metrics/image_metrics.h"

namespace es {

double PhotometricLoss(const double* rendered, const cv::Mat& target,
                       double ssim_weight, double scale, double* d_rendered) {
  CHECK_EQ(target.channels(), 3);
  const cv::Mat x(target.rows, target.cols, CV_64FC3,
                  const_cast<double*>(rendered));
  cv::Mat y;
  target.convertTo(y, CV_64F);
  cv::Mat d_l1, d_ssim;
  cv::Mat* want_l1 = d_rendered ? &d_l1 : nullptr;
  cv::Mat* want_ssim = d_rendered && ssim_weight != 0 ? &d_ssim : nullptr;
  const double l1 = L1Loss(x, y, want_l1);
  const double ssim = ssim_weight != 0 ? Ssim(x, y, want_ssim) : 1.0;
  if (d_rendered) {
    const size_t n = x.total() * 3;
    const double* g1 = d_l1.ptr<double>();
    const double a = scale * (1 - ssim_weight);
    if (want_ssim) {
      const double* g2 = d_ssim.ptr<double>();
      const double b = -scale * ssim_weight;
      for (size_t i = 0; i < n; ++i) d_rendered[i] = a * g1[i] + b * g2[i];
    } else {
      for (size_t i = 0; i < n; ++i) d_rendered[i] = a * g1[i];
    }
  }
  return (1 - ssim_weight) * l1 + ssim_weight * (1 - ssim);
}

}  // namespace es
