#include "costs/mask_bce_loss.h"

#include <glog/logging.h>

#include "core/base/stage_profile.h"

namespace es {

double MaskBceLoss(const double* probability, const cv::Mat& mask, double scale,
                   double* d_probability) {
  ScopedStage timer(Stage::kLossBce);
  CHECK_EQ(mask.channels(), 1);
  const int n = mask.rows * mask.cols;
  // Read in place (no per-call conversion) in the mask types frames hold.
  if (mask.isContinuous() && mask.depth() == CV_32F) {
    return MaskBceMean(probability, mask.ptr<float>(), n, scale,
                       d_probability);
  }
  if (mask.isContinuous() && mask.depth() == CV_64F) {
    return MaskBceMean(probability, mask.ptr<double>(), n, scale,
                       d_probability);
  }
  cv::Mat m;
  mask.convertTo(m, CV_64F);
  return MaskBceMean(probability, m.ptr<double>(), n, scale, d_probability);
}

}  // namespace es
