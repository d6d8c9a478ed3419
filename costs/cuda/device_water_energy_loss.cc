#include "costs/cuda/device_water_energy_loss.h"

#include <array>

#include <glog/logging.h>

#include "costs/cuda/water_energy_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kChannels = 3;  // RGB, and the opponent channels

OpponentBasis Basis() {
  OpponentBasis basis;
  for (int c = 0; c < kChannels; ++c) {
    for (int j = 0; j < kChannels; ++j) basis.k[c][j] = kWaterOpponent[c][j];
  }
  return basis;
}

}  // namespace

DeviceWaterEnergyLoss::DeviceWaterEnergyLoss(const WaterEnergyOptions& options)
    : options_(options), kernels_(MakeWaterEnergyKernels(options)) {
  const WaterEnergyKernels& kernels = kernels_;
  std::vector<double> taps;
  for (int k = 0; k < options.detail_octaves; ++k) {
    detail_offset_.push_back(taps.size());
    detail_radius_.push_back(static_cast<int>(kernels.detail[k].size()) / 2);
    taps.insert(taps.end(), kernels.detail[k].begin(), kernels.detail[k].end());
    window_offset_.push_back(taps.size());
    window_radius_.push_back(static_cast<int>(kernels.window[k].size()) / 2);
    taps.insert(taps.end(), kernels.window[k].begin(), kernels.window[k].end());
  }
  taps_.Upload(taps);
}

DeviceWaterEnergyLoss::Taps DeviceWaterEnergyLoss::Detail(int k) const {
  return {taps_.data() + detail_offset_[k], detail_radius_[k]};
}

DeviceWaterEnergyLoss::Taps DeviceWaterEnergyLoss::Window(int k) const {
  return {taps_.data() + window_offset_[k], window_radius_[k]};
}

ChannelFloors DeviceWaterEnergyLoss::Floors(int band) const {
  const std::array<double, 3> f =
      RenderedEnergyFloors(options_, kernels_, band);
  return {{f[0], f[1], f[2]}};
}

double DeviceWaterEnergyLoss::Evaluate(
    const float* rendered_a, const float* rendered_b, const float* input_a,
    const float* input_b, const float* mask_a, const float* mask_b, int width,
    int height, double scale, float* d_a, float* d_b,
    WaterEnergyTerms* terms) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  CHECK_EQ(mask_a == nullptr, mask_b == nullptr)
      << "DeviceWaterEnergyLoss: both masks or neither";
  const int w = width, h = height;
  const long long pixels = static_cast<long long>(w) * h;
  const size_t plane = static_cast<size_t>(pixels);
  const int blocks = WaterEnergyBlocks(pixels);
  const int octaves = options_.detail_octaves;
  const bool motion = options_.motion_weight != 0;
  const bool detail = options_.detail_weight != 0;
  const bool gradient = d_a != nullptr || d_b != nullptr;

  // The sums, a segment of partials each: the 3 water counts (water_a,
  // water_b, either), the motion term's 3 channels, then per band k the
  // detail term's 6 planes (frame A's channels, then B's).
  const int segments = kChannels + (motion ? kChannels : 0) +
                       (detail ? 2 * kChannels * octaves : 0);
  partials_.Resize(static_cast<size_t>(segments) * blocks);
  sums_.Resize(segments);
  double* counts = sums_.data();
  water_.Resize(3 * plane);
  WaterPlanes(pixels, mask_a, mask_b, water_.data(), partials_.data());
  SumSegments(kChannels, blocks, partials_.data(), counts);

  // y: the opponent channels of rendered A, B, input A, B (12 planes).
  const OpponentBasis basis = Basis();
  y_.Resize(12 * plane);
  OpponentPlanes(pixels, basis, rendered_a, rendered_b, input_a, input_b,
                 y_.data());
  // dy: d loss / d y of render A's 3 channels, then B's.
  if (gradient) {
    dy_.Resize(6 * plane);
    dy_.Zero();
  }
  scratch_.Resize(12 * plane);
  square_.Resize(12 * plane);
  energy_.Resize(12 * plane);
  d_e_.Resize(6 * plane);
  g_.Resize(6 * plane);
  double* d_e = gradient ? d_e_.data() : nullptr;
  // Each opponent channel on its own, averaged, as the CPU.
  const double channel_scale = scale / kChannels;
  double* next_partials = partials_.data() + kChannels * blocks;

  if (motion) {
    // energy = W_0 (y_B - y_A)^2 of the renders (3 planes), then inputs.
    diff_.Resize(6 * plane);
    MotionDifferences(pixels, y_.data(), diff_.data(), square_.data());
    const Taps window = Window(0);
    ClampedBlur(6, w, h, window.taps, window.radius, square_.data(),
                scratch_.data(), energy_.data());
    AmplitudeTerms(kChannels, kChannels, pixels, energy_.data(),
                   energy_.data() + 3 * plane, water_.data() + 2 * plane,
                   counts + 2, Floors(-1), options_.eps,
                   channel_scale * options_.motion_weight, d_e,
                   next_partials);
    next_partials += kChannels * blocks;
    if (gradient) {
      ClampedBlurAdjoint(kChannels, w, h, window.taps, window.radius, d_e,
                         scratch_.data(), g_.data());
      AddMotionGradient(pixels, diff_.data(), g_.data(), dy_.data());
    }
  }
  if (detail) {
    // Band k of all 12 planes: (G_{k-1} or identity) y - G_k y; its
    // energy under W_k; the renders' 6 planes scored against the inputs'.
    const double band_scale =
        0.5 * channel_scale * options_.detail_weight / octaves;
    high_.Resize(12 * plane);
    coarse_.Resize(12 * plane);
    if (octaves > 1) low_.Resize(12 * plane);
    for (int k = 0; k < octaves; ++k) {
      const double* fine = y_.data();
      if (k > 0) {
        const Taps finer = Detail(k - 1);
        ClampedBlur(12, w, h, finer.taps, finer.radius, y_.data(),
                    scratch_.data(), low_.data());
        fine = low_.data();
      }
      const Taps blur = Detail(k), window = Window(k);
      ClampedBlur(12, w, h, blur.taps, blur.radius, y_.data(),
                  scratch_.data(), coarse_.data());
      BandAndSquare(12 * pixels, fine, coarse_.data(), high_.data(),
                    square_.data());
      ClampedBlur(12, w, h, window.taps, window.radius, square_.data(),
                  scratch_.data(), energy_.data());
      AmplitudeTerms(2 * kChannels, kChannels, pixels, energy_.data(),
                     energy_.data() + 6 * plane, water_.data(), counts,
                     Floors(k), options_.eps, band_scale, d_e,
                     next_partials);
      next_partials += 2 * kChannels * blocks;
      if (!gradient) continue;
      // d y += (G_{k-1}^T - G_k^T) (2 high W_k^T d_e), renders only.
      ClampedBlurAdjoint(6, w, h, window.taps, window.radius, d_e,
                         scratch_.data(), g_.data());
      ScaleByTwice(6 * pixels, high_.data(), g_.data());
      ClampedBlurAdjoint(6, w, h, blur.taps, blur.radius, g_.data(),
                         scratch_.data(), coarse_.data());
      const double* fine_adjoint = g_.data();
      if (k > 0) {
        const Taps finer = Detail(k - 1);
        ClampedBlurAdjoint(6, w, h, finer.taps, finer.radius, g_.data(),
                           scratch_.data(), low_.data());
        fine_adjoint = low_.data();
      }
      AddBandGradient(6 * pixels, fine_adjoint, coarse_.data(), dy_.data());
    }
  }
  if (gradient) AddRgbGradients(pixels, basis, dy_.data(), d_a, d_b);
  if (segments > kChannels) {  // (no launch of no blocks: both weights 0)
    SumSegments(segments - kChannels, blocks,
                partials_.data() + kChannels * blocks,
                sums_.data() + kChannels);
  }
  const std::vector<double> sums = sums_.Download();

  // The CPU's means and order: per channel its motion term, then its
  // detail over the frames and bands; the channels' sum.
  // A sum over the water of mask 0 (A), 1 (B) or 2 (either), / its count.
  auto mean = [&](double sum, int mask) {
    return sums[mask] > 0 ? sum / sums[mask] : 0.0;
  };
  WaterEnergyTerms t;
  int at = kChannels;
  if (motion) {
    for (int c = 0; c < kChannels; ++c)
      t.motion += mean(sums[at + c], 2) / kChannels;
    at += kChannels;
  }
  if (detail) {
    for (int c = 0; c < kChannels; ++c) {
      double channel = 0;
      for (int f = 0; f < 2; ++f) {
        for (int k = 0; k < octaves; ++k) {
          const double sum = sums[at + 2 * kChannels * k + kChannels * f + c];
          channel += 0.5 * mean(sum, f) / (kChannels * octaves);
        }
      }
      t.detail += channel;
    }
  }
  if (terms != nullptr) *terms = t;
  return scale * (options_.motion_weight * t.motion +
                  options_.detail_weight * t.detail);
}

}  // namespace cuda
}  // namespace es
