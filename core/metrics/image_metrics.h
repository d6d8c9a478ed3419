#ifndef EULERSPLAT_CORE_METRICS_IMAGE_METRICS_H_
#define EULERSPLAT_CORE_METRICS_IMAGE_METRICS_H_

#include <opencv2/core.hpp>

#include "core/metrics/ssim_kernels.h"

namespace es {

// Image losses and quality metrics on CV_64F images (any channel count; a
// rendered RenderResult buffer wraps as cv::Mat(H, W, CV_64FC3, data)).
//
// SSIM uses an 11x11 Gaussian window (sigma 1.5), C1 = 0.01^2, C2 = 0.03^2
// and a zero-padded 'same' convolution, as the 3DGS reference code does, so
// the SSIM map has one value per pixel and channel and border pixels count
// (the constants: core/metrics/ssim_kernels.h).

// Mean absolute difference over pixels and channels. If d_x is not null it
// receives d loss / d x (same size as x; sign(x - y) / count).
double L1Loss(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x = nullptr);

// Mean SSIM over pixels and channels. If d_x is not null it receives
// d mean_ssim / d x (analytic, exact for the zero-padded convolution).
// Computed in double by core/metrics/ssim.h, which training uses directly
// (in float, with the target's statistics kept between iterations).
double Ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x = nullptr);

// Per-pixel, per-channel SSIM map (same size and type as x).
cv::Mat SsimMap(const cv::Mat& x, const cv::Mat& y);

// PSNR for a peak value of 1 (images in [0, 1]); capped at 100 dB when the
// images are identical.
double Psnr(const cv::Mat& x, const cv::Mat& y);

// Variants restricted to the pixels where mask (CV_32FC1 or CV_64FC1, H x W)
// is > 0.5; with `invert` the pixels where it is <= 0.5. They return NaN when
// the region is empty so an average over frames can skip it.
double MaskedPsnr(const cv::Mat& x, const cv::Mat& y, const cv::Mat& mask,
                  bool invert = false);
double MaskedSsim(const cv::Mat& x, const cv::Mat& y, const cv::Mat& mask,
                  bool invert = false);

// The pixels farther than `distance` pixels from every pixel where `mask`
// (as above) is > 0.5, as a CV_64FC1 mask of 1 there and 0 elsewhere; all 1
// where the mask has no water.
cv::Mat FarFromMask(const cv::Mat& mask, double distance);

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_IMAGE_METRICS_H_
