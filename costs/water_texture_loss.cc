#include "costs/water_texture_loss.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <glog/logging.h>

#include "core/metrics/random_direction.h"
#include "core/base/stage_profile.h"
#include "costs/water_energy_terms.h"
#include "costs/water_kernels.h"

namespace es {
namespace {

constexpr int kChannels = internal::kWaterChannels;
constexpr int kNeighbours = 9;  // 3 x 3
// Rows of the projections that one thread updates at a time: small enough
// for their n x projections block to stay in cache across the features.
constexpr long kRowBlock = 512;

// Offset o of the 3 x 3 neighbourhood, spaced `step` pixels, clamped.
inline int Neighbour(int x, int y, int o, int step, int w, int h) {
  const int nx = std::clamp(x + (o % 3 - 1) * step, 0, w - 1);
  const int ny = std::clamp(y + (o / 3 - 1) * step, 0, h - 1);
  return ny * w + nx;
}

}  // namespace

WaterTextureLoss::WaterTextureLoss(const WaterTextureOptions& options)
    : options_(options), inputs_(options.input_cache_bytes) {
  CHECK_GE(options.bands, 1);
  CHECK_GE(options.projections, 1);
  CHECK_GT(options.sigma, 0);
  for (int k = 0; k < options.bands; ++k)
    kernels_.push_back(
        WaterEnergyGaussian(options.sigma * std::ldexp(1.0, k)));
}

int WaterTextureLoss::dims() const {
  return kChannels * options_.bands * kNeighbours;
}

void WaterTextureLoss::Bands(const double* rgb, std::mt19937_64* noise,
                             std::vector<std::vector<double>>* bands) {
  const size_t pixels = static_cast<size_t>(w_) * h_;
  bands->resize(kChannels * options_.bands);
  // The noise drawn channel by channel in one stream, then the channels'
  // bands in parallel.
  for (int c = 0; c < kChannels; ++c) {
    ChannelWork& work = channels_[c];
    internal::ChannelOf(rgb, pixels, c, &work.channel);
    if (noise != nullptr && options_.input_noise[c] > 0) {
      std::normal_distribution<double> normal(0.0, options_.input_noise[c]);
      for (double& v : work.channel) v += normal(*noise);
    }
  }
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < kChannels; ++c) {
    ChannelWork& work = channels_[c];
    internal::Bands(work.channel, w_, h_, options_.bands, kernels_,
                    &work.blur, &work.low, &work.coarse,
                    &(*bands)[c * options_.bands]);
  }
}

void WaterTextureLoss::FindInputs(const cv::Mat& input,
                                  internal::TextureInputs* out) {
  const size_t pixels = static_cast<size_t>(w_) * h_;
  out->water.clear();
  for (size_t p = 0; p < pixels; ++p)
    if (mask_[p] > 0) out->water.push_back(static_cast<int>(p));
  out->taps.resize(options_.bands);
  for (int k = 0; k < options_.bands; ++k) {
    std::vector<int>& taps = out->taps[k];
    taps.resize(out->water.size() * kNeighbours);
    for (size_t i = 0; i < out->water.size(); ++i) {
      const int x = out->water[i] % w_, y = out->water[i] / w_;
      for (int o = 0; o < kNeighbours; ++o)
        taps[i * kNeighbours + o] = Neighbour(x, y, o, 1 << k, w_, h_);
    }
  }
  input.convertTo(input_, CV_64FC3);
  Bands(input_.ptr<double>(), nullptr, &out->bands);
}

TextureProjection WaterTextureLoss::Projection(
    const std::vector<std::vector<double>>& bands) {
  band_pointers_.clear();
  for (const std::vector<double>& band : bands)
    band_pointers_.push_back(band.data());
  tap_pointers_.clear();
  for (const std::vector<int>& taps : inputs_now_->taps)
    tap_pointers_.push_back(taps.data());
  TextureProjection p;
  p.bands = band_pointers_.data();
  p.count = static_cast<int>(bands.size());
  p.levels = options_.bands;
  p.taps = tap_pointers_.data();
  p.n = static_cast<long>(inputs_now_->water.size());
  p.directions = directions_.data();
  p.projections = options_.projections;
  return p;
}

void WaterTextureLoss::Project(const std::vector<std::vector<double>>& bands,
                               std::vector<double>* out) {
  const TextureProjection p = Projection(bands);
  out->resize(p.n * p.projections);
  const long blocks = (p.n + kRowBlock - 1) / kRowBlock;
  const WaterKernelSet& kernels = WaterKernels();
  // Each block is its own rows, so the threads do not change the sums.
#pragma omp parallel for schedule(static)
  for (long k = 0; k < blocks; ++k)
    kernels.project(p, k * kRowBlock, std::min(p.n, (k + 1) * kRowBlock),
                    out->data());
}

double WaterTextureLoss::Evaluate(const double* rendered,
                                  const cv::Mat& input, const cv::Mat& mask,
                                  double scale, uint64_t draw,
                                  double* d_rendered) {
  ScopedStage timer(Stage::kLossEnergy);
  CHECK(input.type() == CV_32FC3 || input.type() == CV_64FC3)
      << input.type();
  w_ = input.cols;
  h_ = input.rows;
  const size_t pixels = static_cast<size_t>(w_) * h_;
  const double factor = options_.weight * scale;
  if (factor == 0) return 0;
  internal::WaterOf(mask, pixels, &mask_);
  size_t n = 0;
  for (double m : mask_) n += m > 0;
  if (n < 2) return 0;
  // The water pixels, their taps and the input's bands, each computed
  // once while the cache has room.
  const size_t bytes =
      n * sizeof(int) * (1 + kNeighbours * options_.bands) +
      kChannels * options_.bands * pixels * sizeof(double);
  inputs_now_ = &inputs_.Get({&input, &mask}, bytes,
                             [&](internal::TextureInputs* inputs) {
                               FindInputs(input, inputs);
                             });

  // Its own stream: the directions below stay those of `draw`.
  std::mt19937_64 noise(draw ^ 0x9e3779b97f4a7c15ULL);
  Bands(rendered, &noise, &rendered_bands_);

  const int projections = options_.projections;
  std::mt19937_64 rng(draw);
  std::normal_distribution<double> normal;
  std::vector<double> theta(dims());
  directions_.resize(dims(), projections);
  for (int j = 0; j < projections; ++j) {
    DrawUnitDirection(&rng, &normal, &theta);
    directions_.col(j) = Eigen::Map<const Eigen::VectorXd>(theta.data(),
                                                            dims());
  }
  Project(rendered_bands_, &proj_r_);
  Project(inputs_now_->bands, &proj_i_);

  // Per direction: both sets sorted, rank r of the render meets rank r of
  // the input. Each direction writes its own column and sum, so the
  // result does not depend on the threads.
  d_proj_.resize(n * projections);
  std::vector<double> distances(projections);
  const double step = factor / (static_cast<double>(n) * projections);
  sorts_.resize(projections);
#pragma omp parallel for schedule(static)
  for (int j = 0; j < projections; ++j) {
    DirectionSort& s = sorts_[j];
    SortedValues(&proj_i_[j * n], static_cast<int>(n), &s.scratch,
                 &s.input_sorted);
    SortedOrder(&proj_r_[j * n], static_cast<int>(n), 1, &s.scratch,
                &s.rendered_order);
    double sum = 0;
    for (size_t r = 0; r < n; ++r) {
      const int k = s.rendered_order[r];
      const double diff = proj_r_[j * n + k] - s.input_sorted[r];
      sum += std::abs(diff);
      d_proj_[j * n + k] = diff > 0 ? step : (diff < 0 ? -step : 0.0);
    }
    distances[j] = sum;
  }
  const double distance =
      std::accumulate(distances.begin(), distances.end(), 0.0);

  if (d_rendered != nullptr) {
    // The projections' adjoint: feature (b, o)'s gradient, scattered to
    // its taps, each band into its own array.
    d_bands_.resize(rendered_bands_.size());
    for (std::vector<double>& d : d_bands_) d.assign(pixels, 0.0);
    const TextureProjection p = Projection(rendered_bands_);
    const WaterKernelSet& kernels = WaterKernels();
    const int num_bands = static_cast<int>(d_bands_.size());
#pragma omp parallel for schedule(dynamic)
    for (int b = 0; b < num_bands; ++b)
      kernels.project_adjoint(p, b, d_proj_.data(), d_bands_[b].data());
#pragma omp parallel for schedule(dynamic, 1)
    for (int c = 0; c < kChannels; ++c) {
      ChannelWork& work = channels_[c];
      work.channel.assign(pixels, 0.0);
      for (int k = 0; k < options_.bands; ++k)
        internal::AddBandAdjoint(d_bands_[c * options_.bands + k], w_, h_, k,
                                 kernels_, &work.blur, &work.low,
                                 &work.coarse, &work.channel);
    }
    for (int c = 0; c < kChannels; ++c)
      internal::AddChannelGradient(channels_[c].channel, c, d_rendered);
  }
  return factor * distance / (static_cast<double>(n) * projections);
}

}  // namespace es
