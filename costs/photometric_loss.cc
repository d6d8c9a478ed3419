#include "costs/photometric_loss.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>

#include "core/base/stage_profile.h"

namespace es {
namespace {

// Mean |x - y| over the n values; with d (zeros on entry) adds
// grad_scale sign(x - y) / n to it. Used without SSIM only: with it, L1 is
// fused into SSIM's sweep.
template <typename Y>
double L1(const double* x, const Y* y, size_t n, double grad_scale,
          double* d) {
  const double inv_n = 1.0 / static_cast<double>(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double diff = x[i] - y[i];
    sum += std::abs(diff);
    if (d) d[i] += grad_scale * inv_n * ((diff > 0) - (diff < 0));
  }
  return sum * inv_n;
}

}  // namespace

PhotometricLoss::PhotometricLoss(double ssim_weight, bool use_double,
                                 size_t ssim_cache_bytes, SimdLevel level)
    : ssim_weight_(ssim_weight),
      use_double_(use_double),
      float_cache_(use_double ? 0 : ssim_cache_bytes),
      double_cache_(use_double ? ssim_cache_bytes : 0),
      float_scratch_(level),
      double_scratch_(level) {}

template <typename T>
double PhotometricLoss::SsimAndL1(const double* rendered,
                                  const cv::Mat& target,
                                  SsimTargetCache<T>* cache,
                                  SsimScratch<T>* scratch,
                                  double ssim_grad_scale,
                                  double l1_grad_scale, double* d_rendered,
                                  double* l1) {
  const SsimTarget<T>& stats = cache->Get(target, scratch);
  return SsimAndL1AgainstTarget(rendered, stats, scratch, ssim_grad_scale,
                                l1_grad_scale, d_rendered, l1);
}

double PhotometricLoss::Evaluate(const double* rendered,
                                 const cv::Mat& target, double scale,
                                 double* d_rendered) {
  CHECK_EQ(target.channels(), 3);
  CHECK(target.depth() == CV_32F || target.depth() == CV_64F);
  CHECK(target.isContinuous());
  const size_t n = target.total() * 3;
  const double a = scale * (1 - ssim_weight_);
  double l1 = 0, ssim = 1;
  if (ssim_weight_ != 0) {
    // L1 is fused into SSIM's sweep (it reads the same values).
    ScopedStage timer(Stage::kLossSsim);
    const double b = -scale * ssim_weight_;
    ssim = use_double_
               ? SsimAndL1(rendered, target, &double_cache_, &double_scratch_,
                           b, a, d_rendered, &l1)
               : SsimAndL1(rendered, target, &float_cache_, &float_scratch_,
                           b, a, d_rendered, &l1);
  } else {
    ScopedStage timer(Stage::kLossL1);
    if (d_rendered) std::fill(d_rendered, d_rendered + n, 0.0);
    l1 = target.depth() == CV_32F
             ? L1(rendered, target.ptr<float>(), n, a, d_rendered)
             : L1(rendered, target.ptr<double>(), n, a, d_rendered);
  }
  return (1 - ssim_weight_) * l1 + ssim_weight_ * (1 - ssim);
}

}  // namespace es
