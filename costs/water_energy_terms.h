#ifndef EULERSPLAT_COSTS_WATER_ENERGY_TERMS_H_
#define EULERSPLAT_COSTS_WATER_ENERGY_TERMS_H_

// What the water energy loss (costs/water_energy_loss.h) and its device
// twin (costs/cuda/device_water_energy_loss.h) share, without OpenCV: the
// options, the terms, the opponent colour basis and the blur kernels.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glog/logging.h>

namespace es {

// See WaterEnergyLoss for what each term measures.
struct WaterEnergyOptions {
  double motion_weight = 1.0;
  double detail_weight = 1.0;
  double detail_sigma = 1.0;  // pixels: what G keeps is "texture"
  double window_sigma = 2.0;  // pixels: the neighbourhood an energy covers
  int detail_octaves = 1;     // bands of the detail term, finest first
  // Floor of the energies (an amplitude of 1e-3 of the 0..1 range): keeps
  // the gradient finite where a render is perfectly flat.
  double eps = 1e-6;
  // Std of the input's per-pixel noise on each opponent channel
  // (costs/water_input_noise.h). Its expected energy in each term is
  // added to the render's before the comparison: the input's change and
  // texture hold that noise, which no model should place.
  std::array<double, 3> input_noise = {0, 0, 0};
  // What the inputs' own energies may keep between calls (the CPU loss:
  // costs/input_cache.h): every frame's of a 224 x 168 clip of 54
  // training frames takes 98 MB.
  size_t input_cache_bytes = size_t{128} << 20;
};

// The loss's terms, unweighted.
struct WaterEnergyTerms {
  double motion = 0;
  double detail = 0;  // mean of the two frames'
};

// An orthonormal opponent colour basis: luminance, red-green,
// yellow-blue, one row per channel. Water's change and texture are mostly
// of luminance; in RGB, a render could match each channel's amplitude
// with a tint that flickers (red up while green goes down), which the
// chroma rows count.
constexpr double kWaterOpponent[3][3] = {
    {0.57735026918962576, 0.57735026918962576, 0.57735026918962576},
    {0.70710678118654752, -0.70710678118654752, 0.0},
    {0.40824829046386302, 0.40824829046386302, -0.81649658092772603}};

// A normalized Gaussian of `sigma` pixels, radius max(1, ceil(3 sigma)):
// the taps of the loss's blurs.
inline std::vector<double> WaterEnergyGaussian(double sigma) {
  CHECK_GT(sigma, 0);
  const int radius = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
  std::vector<double> k(2 * radius + 1);
  double sum = 0;
  for (int i = -radius; i <= radius; ++i) {
    k[i + radius] = std::exp(-0.5 * i * i / (sigma * sigma));
    sum += k[i + radius];
  }
  for (double& v : k) v /= sum;
  return k;
}

// The blurs of the detail bands k < detail_octaves: G_k of detail_sigma
// 2^k and W_k of window_sigma 2^k pixels (W_0 is also the motion term's
// window); noise_gain[k]: the share of white noise's variance that band k
// keeps, the sum of its 2D filter's squared taps.
struct WaterEnergyKernels {
  std::vector<std::vector<double>> detail, window;
  std::vector<double> noise_gain;
};

// sum_i a_i b_i of two odd-length kernels aligned at their centres.
inline double CentredDot(const std::vector<double>& a,
                         const std::vector<double>& b) {
  const int ra = static_cast<int>(a.size()) / 2;
  const int rb = static_cast<int>(b.size()) / 2;
  double sum = 0;
  for (int i = -std::min(ra, rb); i <= std::min(ra, rb); ++i)
    sum += a[i + ra] * b[i + rb];
  return sum;
}

// sum over the 2D taps of (a x a - b x b)^2, a and b 1D kernels: band k's
// filter G_{k-1} - G_k (G_{-1} = identity) is separable in two terms.
inline double SeparableDifferenceSquares(const std::vector<double>& a,
                                         const std::vector<double>& b) {
  const double aa = CentredDot(a, a), ab = CentredDot(a, b),
               bb = CentredDot(b, b);
  return aa * aa - 2 * ab * ab + bb * bb;
}

inline WaterEnergyKernels MakeWaterEnergyKernels(
    const WaterEnergyOptions& options) {
  CHECK_GT(options.eps, 0);
  CHECK_GE(options.detail_octaves, 1);
  WaterEnergyKernels kernels;
  for (int k = 0; k < options.detail_octaves; ++k) {
    const double octave = std::ldexp(1.0, k);
    kernels.detail.push_back(
        WaterEnergyGaussian(options.detail_sigma * octave));
    kernels.window.push_back(
        WaterEnergyGaussian(options.window_sigma * octave));
    const std::vector<double> finer =
        k == 0 ? std::vector<double>{1.0} : kernels.detail[k - 1];
    kernels.noise_gain.push_back(
        SeparableDifferenceSquares(finer, kernels.detail[k]));
  }
  return kernels;
}

// The floors that the rendered energies get on each opponent channel: eps
// plus the input noise's expected energy in the term (the motion term's
// difference of two frames has twice the noise's variance; band k keeps
// noise_gain[k] of it). band < 0: the motion term.
inline std::array<double, 3> RenderedEnergyFloors(
    const WaterEnergyOptions& options, const WaterEnergyKernels& kernels,
    int band) {
  const double gain = band < 0 ? 2.0 : kernels.noise_gain[band];
  std::array<double, 3> floors;
  for (int c = 0; c < 3; ++c)
    floors[c] = options.eps +
                gain * options.input_noise[c] * options.input_noise[c];
  return floors;
}

}  // namespace es

#endif  // EULERSPLAT_COSTS_WATER_ENERGY_TERMS_H_
