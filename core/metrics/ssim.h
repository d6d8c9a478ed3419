#ifndef EULERSPLAT_CORE_METRICS_SSIM_H_
#define EULERSPLAT_CORE_METRICS_SSIM_H_

// The cv::Mat entry point of SSIM against a kept target
// (core/metrics/ssim_target.h): float in training, double for the metrics
// and the gradient tests.

#include <opencv2/core.hpp>

#include "core/metrics/ssim_target.h"

namespace es {

// Fills *target from y (CV_32F or CV_64F, any channel count, continuous).
template <typename T>
void ComputeSsimTarget(const cv::Mat& y, SsimScratch<T>* scratch,
                       SsimTarget<T>* target);

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_SSIM_H_
