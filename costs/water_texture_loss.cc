#include "costs/water_texture_loss.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <glog/logging.h>

#include "core/metrics/random_direction.h"
#include "core/base/stage_profile.h"
#include "costs/water_energy_terms.h"

namespace es {
namespace {

constexpr int kChannels = internal::kWaterChannels;
constexpr int kNeighbours = 9;  // 3 x 3
// Rows of the projections that one thread updates at a time: small enough
// for their n x projections block to stay in cache across the features.
constexpr Eigen::Index kRowBlock = 512;

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

void WaterTextureLoss::Bands(const double* rgb, std::mt19937_64* noise,
                             std::vector<std::vector<double>>* bands) {
  const size_t pixels = static_cast<size_t>(w_) * h_;
  bands->resize(kChannels * options_.bands);
  for (int c = 0; c < kChannels; ++c) {
    internal::ChannelOf(rgb, pixels, c, &channel_);
    if (noise != nullptr && options_.input_noise[c] > 0) {
      std::normal_distribution<double> normal(0.0, options_.input_noise[c]);
      for (double& v : channel_) v += normal(*noise);
    }
    internal::Bands(channel_, w_, h_, options_.bands, kernels_, &blur_,
                    &low_, &coarse_, &(*bands)[c * options_.bands]);
  }
}

void WaterTextureLoss::FindTaps() {
  taps_.resize(options_.bands);
  for (int k = 0; k < options_.bands; ++k) {
    taps_[k].resize(water_.size() * kNeighbours);
    for (size_t i = 0; i < water_.size(); ++i) {
      const int x = water_[i] % w_, y = water_[i] / w_;
      for (int o = 0; o < kNeighbours; ++o)
        taps_[k][i * kNeighbours + o] = Neighbour(x, y, o, 1 << k, w_, h_);
    }
  }
}

void WaterTextureLoss::Project(const std::vector<std::vector<double>>& bands,
                               Eigen::MatrixXd* out) {
  const Eigen::Index n = static_cast<Eigen::Index>(water_.size());
  out->setZero(n, options_.projections);
  const Eigen::Index blocks = (n + kRowBlock - 1) / kRowBlock;
  // Per block of pixels, feature (b, o) of each at once times its row of
  // the directions: no n x dims feature matrix is ever held. Each block
  // is its own rows, so the threads do not change the sums.
#pragma omp parallel for schedule(static)
  for (Eigen::Index k = 0; k < blocks; ++k) {
    const Eigen::Index begin = k * kRowBlock;
    const Eigen::Index rows = std::min(kRowBlock, n - begin);
    Eigen::VectorXd values(rows);
    auto block = out->middleRows(begin, rows);
    for (size_t b = 0; b < bands.size(); ++b) {
      const int* taps = taps_[b % options_.bands].data() + begin * kNeighbours;
      const double* band = bands[b].data();
      for (int o = 0; o < kNeighbours; ++o) {
        for (Eigen::Index i = 0; i < rows; ++i)
          values[i] = band[taps[i * kNeighbours + o]];
        block.noalias() += values * directions_.row(b * kNeighbours + o);
      }
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
  // Its own stream: the directions below stay those of `draw`.
  std::mt19937_64 noise(draw ^ 0x9e3779b97f4a7c15ULL);
  Bands(rendered, &noise, &rendered_bands_);
  Bands(input_.ptr<double>(), nullptr, &input_bands_);
  FindTaps();

  const size_t n = water_.size();
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
  Project(input_bands_, &proj_i_);

  // Per direction: both sets sorted, rank r of the render meets rank r of
  // the input. Each direction writes its own column and sum, so the
  // result does not depend on the threads.
  d_proj_.resize(static_cast<Eigen::Index>(n), projections);
  std::vector<double> distances(projections);
  const double step = factor / (static_cast<double>(n) * projections);
  sorts_.resize(projections);
#pragma omp parallel for schedule(static)
  for (int j = 0; j < projections; ++j) {
    DirectionSort& s = sorts_[j];
    SortedOrder(proj_i_.col(j).data(), static_cast<int>(n), 1, &s.scratch,
                &s.input_order);
    SortedOrder(proj_r_.col(j).data(), static_cast<int>(n), 1, &s.scratch,
                &s.rendered_order);
    double sum = 0;
    for (size_t r = 0; r < n; ++r) {
      const int k = s.rendered_order[r];
      const double diff = proj_r_(k, j) - proj_i_(s.input_order[r], j);
      sum += std::abs(diff);
      d_proj_(k, j) = diff > 0 ? step : (diff < 0 ? -step : 0.0);
    }
    distances[j] = sum;
  }
  const double distance =
      std::accumulate(distances.begin(), distances.end(), 0.0);

  if (d_rendered != nullptr) {
    // The projections' adjoint: feature (b, o)'s gradient, scattered to
    // its taps.
    d_bands_.resize(rendered_bands_.size());
    for (std::vector<double>& d : d_bands_) d.assign(pixels, 0.0);
    const int num_bands = static_cast<int>(d_bands_.size());
#pragma omp parallel for schedule(dynamic)
    for (int b = 0; b < num_bands; ++b) {  // each band its own array
      const std::vector<int>& taps = taps_[b % options_.bands];
      double* d = d_bands_[b].data();
      Eigen::VectorXd values(static_cast<Eigen::Index>(n));
      for (int o = 0; o < kNeighbours; ++o) {
        values.noalias() =
            d_proj_ * directions_.row(b * kNeighbours + o).transpose();
        for (size_t i = 0; i < n; ++i)
          d[taps[i * kNeighbours + o]] += values[i];
      }
    }
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
