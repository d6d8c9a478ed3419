#include "costs/water_texture_loss.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <glog/logging.h>

#include "core/metrics/random_direction.h"
#include "core/profile/stage_profile.h"
#include "costs/water_energy_terms.h"

namespace es {
namespace {

constexpr int kChannels = internal::kWaterChannels;
constexpr int kNeighbours = 9;  // 3 x 3

// Offset o of the 3 x 3 neighbourhood, spaced `step` pixels, clamped.
inline int Neighbour(int x, int y, int o, int step, int w, int h) {
  const int nx = std::clamp(x + (o % 3 - 1) * step, 0, w - 1);
  const int ny = std::clamp(y + (o / 3 - 1) * step, 0, h - 1);
  return ny * w + nx;
}

}  // namespace

WaterTextureLoss::WaterTextureLoss(const WaterTextureOptions& options)
    : options_(options) {
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

void WaterTextureLoss::Bands(const double* rgb,
                             std::vector<std::vector<double>>* bands) {
  const size_t pixels = static_cast<size_t>(w_) * h_;
  bands->resize(kChannels * options_.bands);
  for (int c = 0; c < kChannels; ++c) {
    internal::ChannelOf(rgb, pixels, c, &channel_);
    for (int k = 0; k < options_.bands; ++k)
      internal::Band(channel_, w_, h_, k, kernels_, &blur_, &low_,
                     &(*bands)[c * options_.bands + k]);
  }
}

void WaterTextureLoss::Project(const std::vector<std::vector<double>>& bands,
                               const std::vector<double>& theta,
                               std::vector<double>* out) const {
  out->assign(water_.size(), 0.0);
  for (size_t b = 0; b < bands.size(); ++b) {
    const int step = 1 << (static_cast<int>(b) % options_.bands);
    const double* band = bands[b].data();
    const double* t = theta.data() + b * kNeighbours;
    for (size_t i = 0; i < water_.size(); ++i) {
      const int x = water_[i] % w_, y = water_[i] / w_;
      double sum = 0;
      for (int o = 0; o < kNeighbours; ++o)
        sum += t[o] * band[Neighbour(x, y, o, step, w_, h_)];
      (*out)[i] += sum;
    }
  }
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
  internal::WaterOf(mask, pixels, &mask_);
  water_.clear();
  for (size_t p = 0; p < pixels; ++p)
    if (mask_[p] > 0) water_.push_back(static_cast<int>(p));
  const double factor = options_.weight * scale;
  if (water_.size() < 2 || factor == 0) return 0;

  input.convertTo(input_, CV_64FC3);
  Bands(rendered, &rendered_bands_);
  Bands(input_.ptr<double>(), &input_bands_);
  d_bands_.assign(rendered_bands_.size(), std::vector<double>(pixels, 0.0));

  const size_t n = water_.size();
  const int projections = options_.projections;
  std::mt19937_64 rng(draw);
  std::normal_distribution<double> normal;
  theta_.resize(dims());
  order_.resize(n);
  d_proj_.resize(n);
  double distance = 0;
  for (int j = 0; j < projections; ++j) {
    DrawUnitDirection(&rng, &normal, &theta_);
    Project(rendered_bands_, theta_, &proj_r_);
    Project(input_bands_, theta_, &proj_i_);
    std::sort(proj_i_.begin(), proj_i_.end());
    std::iota(order_.begin(), order_.end(), 0);
    std::sort(order_.begin(), order_.end(),
              [this](int a, int b) { return proj_r_[a] < proj_r_[b]; });
    // Rank r of the render meets rank r of the input.
    const double step = factor / (static_cast<double>(n) * projections);
    for (size_t r = 0; r < n; ++r) {
      const double diff = proj_r_[order_[r]] - proj_i_[r];
      distance += std::abs(diff);
      d_proj_[order_[r]] = diff > 0 ? step : (diff < 0 ? -step : 0.0);
    }
    if (d_rendered == nullptr) continue;
    for (size_t b = 0; b < d_bands_.size(); ++b) {
      const int stride = 1 << (static_cast<int>(b) % options_.bands);
      const double* t = theta_.data() + b * kNeighbours;
      double* d = d_bands_[b].data();
      for (size_t i = 0; i < n; ++i) {
        const int x = water_[i] % w_, y = water_[i] / w_;
        for (int o = 0; o < kNeighbours; ++o)
          d[Neighbour(x, y, o, stride, w_, h_)] += t[o] * d_proj_[i];
      }
    }
  }
  if (d_rendered != nullptr) {
    for (int c = 0; c < kChannels; ++c) {
      channel_.assign(pixels, 0.0);
      for (int k = 0; k < options_.bands; ++k)
        internal::AddBandAdjoint(d_bands_[c * options_.bands + k], w_, h_, k,
                                 kernels_, &blur_, &low_, &coarse_,
                                 &channel_);
      internal::AddChannelGradient(channel_, c, d_rendered);
    }
  }
  return factor * distance / (static_cast<double>(n) * projections);
}

}  // namespace es
