#ifndef EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_
#define EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_

#include <array>
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

// The noise std on each opponent colour channel (kWaterOpponent's rows)
// of frames[indices]: per channel the median over the frames of
// HaarNoiseSigma on the pixels that are not water (masks > 0.5 and a
// pixel beside them are skipped: the water's own texture is signal).
// A frame with no usable block is passed over; all zeros if none has one.
std::array<double, 3> EstimateInputNoise(const std::vector<Frame>& frames,
                                         const std::vector<int>& indices);

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_INPUT_NOISE_H_
