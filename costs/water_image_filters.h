#ifndef EULERSPLAT_COSTS_WATER_IMAGE_FILTERS_H_
#define EULERSPLAT_COSTS_WATER_IMAGE_FILTERS_H_

// The image operations that the water losses (costs/water_energy_loss.h,
// costs/water_texture_loss.h) share, each with the adjoint its gradient
// needs: separable Gaussian blurs with clamped borders, the opponent
// colour channels, the bands of a difference-of-Gaussians pyramid and the
// water mask as 0 / 1 weights. Images are row-major doubles, w x h.

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace es {
namespace internal {

constexpr int kWaterChannels = 3;  // RGB, and the opponent channels

// Scratch of a 2D blur: the image between its two passes, one padded
// row, and the row pointers and taps of a pass.
struct BlurScratch {
  std::vector<double> image, line, coefficients;
  std::vector<const double*> sources;
};

// out = k * in along x, then along y (clamped borders), and its adjoint:
// exact at the borders, so that gradients are.
void Blur(const std::vector<double>& in, int w, int h,
          const std::vector<double>& k, BlurScratch* tmp,
          std::vector<double>* out);
void BlurAdjoint(const std::vector<double>& g_out, int w, int h,
                 const std::vector<double>& k, BlurScratch* tmp,
                 std::vector<double>* g_in);

// Opponent channel c (kWaterOpponent's row c) of an H x W x 3 RGB image.
void ChannelOf(const double* rgb, size_t pixels, int c,
               std::vector<double>* out);

// Adds the gradient of opponent channel c back to RGB (the basis'
// transpose); nothing if d_rgb is null.
void AddChannelGradient(const std::vector<double>& d_channel, int c,
                        double* d_rgb);

// 1 where the mask says water (> 0.5; everywhere without a mask), else 0.
// mask: empty, CV_32FC1 or CV_64FC1 of `pixels` pixels.
void WaterOf(const cv::Mat& mask, size_t pixels, std::vector<double>* out);

// Band k of the difference-of-Gaussians pyramid into *out: y - G_0 * y for
// k = 0, else G_{k-1} * y - G_k * y (*low holds G_{k-1} * y then);
// kernels[k] is G_k.
void Band(const std::vector<double>& y, int w, int h, int k,
          const std::vector<std::vector<double>>& kernels, BlurScratch* tmp,
          std::vector<double>* low, std::vector<double>* out);

// Band(y, .., k, ..) for k = 0 .. count - 1 into out[0 .. count - 1],
// each blur once (band k's coarse blur is band k + 1's fine one); *low
// and *next are scratch.
void Bands(const std::vector<double>& y, int w, int h, int count,
           const std::vector<std::vector<double>>& kernels, BlurScratch* tmp,
           std::vector<double>* low, std::vector<double>* next,
           std::vector<double>* out);

// Adds the adjoint of band k applied to g, (G_{k-1}^T - G_k^T) g, to *dy
// (G_{-1} = identity); *low and *coarse are scratch.
void AddBandAdjoint(const std::vector<double>& g, int w, int h, int k,
                    const std::vector<std::vector<double>>& kernels,
                    BlurScratch* tmp, std::vector<double>* low,
                    std::vector<double>* coarse, std::vector<double>* dy);

}  // namespace internal
}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_IMAGE_FILTERS_H_
