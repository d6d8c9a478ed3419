#ifndef EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_
#define EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_

#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/io/scene.h"

namespace es {

// Per-pixel noise of the input frames (sensor or render-sample noise, new
// each frame): part of the water's measured detail and frame-to-frame
// change that no model can place, so the water losses should not ask a
// render for it (costs/water_energy_loss.h, costs/water_texture_loss.h).

// Standard deviation of white noise in one channel (CV_64FC1), by the
// median absolute Haar diagonal detail of 2 x 2 blocks,
// |a - b - c + d| / 2, over 0.6745 (the MAD estimator of wavelet
// denoising): smooth content has next to no diagonal detail, white noise
// of std s gives detail of std s, and the median passes over the minority
// of blocks on edges and fine texture, which only raise it. Blocks with a
// pixel where `skip` (CV_8UC1, may be empty) is non-zero are not used.
// NaN without a usable block.
double HaarNoiseSigma(const cv::Mat& channel, const cv::Mat& skip);

// The noise std of one channel from two consecutive frames of it, `prev`
// and `next` (CV_64FC1, same size; `skip` as above): noise is new each
// frame and white, the scenery is neither.
//  - In time: the frames' difference over sqrt(2) has the noise's std and
//    none of the texture that stays put.
//  - In scale: texture that moves with the camera still leaves detail in
//    that difference, but about as much at twice the pixel size, while
//    the noise's halves there (2 x 2 means of white noise). So with t1,
//    t2 the HaarNoiseSigma of the difference at full and half size,
//    noise^2 = (t1^2 - t2^2) * 4 / 3, and no noise where t2 >= t1.
// Returns {t1, t2}; NaN where no block is usable.
std::array<double, 2> TemporalHaarDetail(const cv::Mat& prev,
                                         const cv::Mat& next,
                                         const cv::Mat& skip);

// The noise std on each opponent colour channel (kWaterOpponent's rows)
// of the frames[indices], from the pairs of them that follow each other
// (indices k and k + 1): per channel, TemporalHaarDetail's two medians
// over the pairs combined as above, and never above the median single-
// frame HaarNoiseSigma. Pixels that are water (masks > 0.5 and a pixel
// beside them, in either frame) are skipped: the water's own change is
// signal. A channel's noise under one 8-bit grey level is 0 (rounding,
// not noise the losses need). All zeros without such a pair: from single
// frames, fine texture and noise cannot be told apart.
std::array<double, 3> EstimateInputNoise(const std::vector<Frame>& frames,
                                         const std::vector<int>& indices);

// Whether any channel of a noise estimate is non-zero.
inline bool HasInputNoise(const std::array<double, 3>& sigma) {
  return sigma[0] > 0 || sigma[1] > 0 || sigma[2] > 0;
}

// Adds white noise of std sigma[c] along each opponent colour channel c
// to `rgb` (CV_64FC3, 0..1), drawn from `seed`: a render then carries the
// input's noise, so figures that measure detail and change (the realism
// ratios) compare like with like. Nothing where every sigma is 0.
void DrawInputNoise(const std::array<double, 3>& sigma, uint64_t seed,
                    cv::Mat* rgb);

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_
