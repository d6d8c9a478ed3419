#include "costs/water_energy_loss.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

#include "core/profile/stage_profile.h"

namespace es {
namespace {

using internal::BlurScratch;

constexpr int kChannels = 3;  // RGB, and the opponent channels

// The blurs below clamp the borders: out[i] = sum_j k[j] in[clamp(i + j -
// r)]. Rows are padded with their clamped ends, and columns are blurred a
// whole row at a time, so every inner loop runs over contiguous memory
// with a fixed kernel tap and vectorizes.

// Along x: each row through a padded copy of itself.
void BlurRows(const double* in, int w, int h, const std::vector<double>& k,
              std::vector<double>* line, double* out) {
  const int r = static_cast<int>(k.size()) / 2;
  line->resize(w + 2 * r);
  double* pad = line->data();
  for (int y = 0; y < h; ++y) {
    const double* src = in + static_cast<size_t>(y) * w;
    double* dst = out + static_cast<size_t>(y) * w;
    for (int m = 0; m < r; ++m) {
      pad[m] = src[0];
      pad[w + r + m] = src[w - 1];
    }
    std::copy(src, src + w, pad + r);
    std::fill(dst, dst + w, 0.0);
    for (int j = 0; j <= 2 * r; ++j) {
      const double kj = k[j];
      const double* shifted = pad + j;
      for (int x = 0; x < w; ++x) dst[x] += kj * shifted[x];
    }
  }
}

// The adjoint of BlurRows: each row's gradient spread into a padded line,
// whose ends fold back onto the clamped border pixels.
void BlurRowsAdjoint(const double* g_out, int w, int h,
                     const std::vector<double>& k, std::vector<double>* line,
                     double* g_in) {
  const int r = static_cast<int>(k.size()) / 2;
  line->resize(w + 2 * r);
  double* pad = line->data();
  for (int y = 0; y < h; ++y) {
    const double* src = g_out + static_cast<size_t>(y) * w;
    double* dst = g_in + static_cast<size_t>(y) * w;
    std::fill(pad, pad + w + 2 * r, 0.0);
    for (int j = 0; j <= 2 * r; ++j) {
      const double kj = k[j];
      double* shifted = pad + j;
      for (int x = 0; x < w; ++x) shifted[x] += kj * src[x];
    }
    std::copy(pad + r, pad + r + w, dst);
    for (int m = 0; m < r; ++m) {
      dst[0] += pad[m];
      dst[w - 1] += pad[w + r + m];
    }
  }
}

// Along y: output row y gathers whole input rows clamp(y + j - r).
void BlurColumns(const double* in, int w, int h, const std::vector<double>& k,
                 double* out) {
  const int r = static_cast<int>(k.size()) / 2;
  for (int y = 0; y < h; ++y) {
    double* dst = out + static_cast<size_t>(y) * w;
    std::fill(dst, dst + w, 0.0);
    for (int j = 0; j <= 2 * r; ++j) {
      const double kj = k[j];
      const double* src =
          in + static_cast<size_t>(std::clamp(y + j - r, 0, h - 1)) * w;
      for (int x = 0; x < w; ++x) dst[x] += kj * src[x];
    }
  }
}

// The adjoint of BlurColumns: input row y scatters into the rows it fed.
void BlurColumnsAdjoint(const double* g_out, int w, int h,
                        const std::vector<double>& k, double* g_in) {
  const int r = static_cast<int>(k.size()) / 2;
  std::fill(g_in, g_in + static_cast<size_t>(w) * h, 0.0);
  for (int y = 0; y < h; ++y) {
    const double* src = g_out + static_cast<size_t>(y) * w;
    for (int j = 0; j <= 2 * r; ++j) {
      const double kj = k[j];
      double* dst =
          g_in + static_cast<size_t>(std::clamp(y + j - r, 0, h - 1)) * w;
      for (int x = 0; x < w; ++x) dst[x] += kj * src[x];
    }
  }
}

// 2D blur (x pass, then y pass) and its adjoint (y, then x), exact at the
// borders so that gradients are.
void Blur(const std::vector<double>& in, int w, int h,
          const std::vector<double>& k, BlurScratch* tmp,
          std::vector<double>* out) {
  tmp->image.resize(in.size());
  out->resize(in.size());
  BlurRows(in.data(), w, h, k, &tmp->line, tmp->image.data());
  BlurColumns(tmp->image.data(), w, h, k, out->data());
}

void BlurAdjoint(const std::vector<double>& g_out, int w, int h,
                 const std::vector<double>& k, BlurScratch* tmp,
                 std::vector<double>* g_in) {
  tmp->image.resize(g_out.size());
  g_in->resize(g_out.size());
  BlurColumnsAdjoint(g_out.data(), w, h, k, tmp->image.data());
  BlurRowsAdjoint(tmp->image.data(), w, h, k, &tmp->line, g_in->data());
}

// Opponent channel c of an H x W x 3 RGB image.
void ChannelOf(const double* rgb, size_t pixels, int c,
               std::vector<double>* out) {
  out->resize(pixels);
  const double* k = kWaterOpponent[c];
  for (size_t p = 0; p < pixels; ++p) {
    const double* v = rgb + kChannels * p;
    (*out)[p] = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  }
}

// Adds the gradient of opponent channel c back to RGB (the basis'
// transpose).
void AddChannelGradient(const std::vector<double>& d_channel, int c,
                        double* d_rgb) {
  if (d_rgb == nullptr) return;
  const double* k = kWaterOpponent[c];
  for (size_t p = 0; p < d_channel.size(); ++p) {
    double* d = d_rgb + kChannels * p;
    d[0] += k[0] * d_channel[p];
    d[1] += k[1] * d_channel[p];
    d[2] += k[2] * d_channel[p];
  }
}

// 1 where the mask says water (or everywhere without a mask), else 0.
void WaterOf(const cv::Mat& mask, size_t pixels, std::vector<double>* out) {
  out->assign(pixels, 1.0);
  if (mask.empty()) return;
  CHECK(mask.type() == CV_32FC1 || mask.type() == CV_64FC1) << mask.type();
  CHECK_EQ(mask.total(), pixels);
  cv::Mat d;
  mask.convertTo(d, CV_64FC1);
  const double* m = d.ptr<double>();
  for (size_t p = 0; p < pixels; ++p) (*out)[p] = m[p] > 0.5 ? 1.0 : 0.0;
}

// Band k of the detail pyramid into *out: y - G_0 * y for k = 0, else
// G_{k-1} * y - G_k * y (*low holds G_{k-1} * y then).
void Band(const std::vector<double>& y, int w, int h, int k,
          const std::vector<std::vector<double>>& kernels, BlurScratch* tmp,
          std::vector<double>* low, std::vector<double>* out) {
  const std::vector<double>* fine = &y;
  if (k > 0) {
    Blur(y, w, h, kernels[k - 1], tmp, low);
    fine = low;
  }
  Blur(y, w, h, kernels[k], tmp, out);
  for (size_t p = 0; p < y.size(); ++p) (*out)[p] = (*fine)[p] - (*out)[p];
}

// Adds the adjoint of band k applied to g, (G_{k-1}^T - G_k^T) g, to *dy
// (G_{-1} = identity); *low and *coarse are scratch.
void AddBandAdjoint(const std::vector<double>& g, int w, int h, int k,
                    const std::vector<std::vector<double>>& kernels,
                    BlurScratch* tmp, std::vector<double>* low,
                    std::vector<double>* coarse, std::vector<double>* dy) {
  const std::vector<double>* fine = &g;
  if (k > 0) {
    BlurAdjoint(g, w, h, kernels[k - 1], tmp, low);
    fine = low;
  }
  BlurAdjoint(g, w, h, kernels[k], tmp, coarse);
  for (size_t p = 0; p < g.size(); ++p) (*dy)[p] += (*fine)[p] - (*coarse)[p];
}

// W * (x^2).
void Energy(const std::vector<double>& x, int w, int h,
            const std::vector<double>& window, BlurScratch* tmp,
            std::vector<double>* square, std::vector<double>* out) {
  square->resize(x.size());
  for (size_t p = 0; p < x.size(); ++p) (*square)[p] = x[p] * x[p];
  Blur(*square, w, h, window, tmp, out);
}

}  // namespace

WaterEnergyLoss::WaterEnergyLoss(const WaterEnergyOptions& options)
    : options_(options), kernels_(MakeWaterEnergyKernels(options)) {}

double WaterEnergyLoss::AmplitudeL1(const std::vector<double>& e_rendered,
                                    const std::vector<double>& e_input,
                                    const std::vector<double>& mask,
                                    double scale,
                                    std::vector<double>* d_energy) const {
  double count = 0;
  for (double m : mask) count += m;
  d_energy->assign(mask.size(), 0.0);
  if (count == 0) return 0;
  double sum = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    if (mask[p] == 0) continue;
    const double a = std::sqrt(std::max(e_rendered[p], 0.0) + options_.eps);
    const double b = std::sqrt(std::max(e_input[p], 0.0) + options_.eps);
    sum += std::abs(a - b);
    const double sign = a > b ? 1.0 : (a < b ? -1.0 : 0.0);
    (*d_energy)[p] = scale * sign / (2 * a * count);
  }
  return sum / count;
}

double WaterEnergyLoss::Evaluate(const double* rendered_a,
                                 const double* rendered_b,
                                 const cv::Mat& input_a,
                                 const cv::Mat& input_b,
                                 const cv::Mat& mask_a, const cv::Mat& mask_b,
                                 double scale, double* d_a, double* d_b,
                                 WaterEnergyTerms* terms) {
  ScopedStage timer(Stage::kLossEnergy);
  CHECK(input_a.size() == input_b.size());
  CHECK(input_a.type() == CV_32FC3 || input_a.type() == CV_64FC3)
      << input_a.type();
  CHECK_EQ(input_a.type(), input_b.type());
  CHECK_EQ(mask_a.empty(), mask_b.empty());
  const int w = input_a.cols, h = input_a.rows;
  const size_t pixels = static_cast<size_t>(w) * h;
  input_a.convertTo(input_a_, CV_64FC3);
  input_b.convertTo(input_b_, CV_64FC3);
  WaterOf(mask_a, pixels, &mask_a_);
  WaterOf(mask_b, pixels, &mask_b_);
  mask_.resize(pixels);
  for (size_t p = 0; p < pixels; ++p)
    mask_[p] = std::max(mask_a_[p], mask_b_[p]);

  // Each opponent channel on its own, averaged: a change of hue that the
  // input does not have is not counted as the input's change.
  const double channel_scale = scale / kChannels;
  // (Small images on one thread: there the fork costs more than it saves.)
  std::array<double, kChannels> motion{}, detail{};
#pragma omp parallel for schedule(dynamic, 1) if (pixels >= 16384)
  for (int c = 0; c < kChannels; ++c) {
    EvaluateChannel(c, rendered_a, rendered_b, w, h, channel_scale,
                    &channels_[c], &motion[c], &detail[c]);
  }
  WaterEnergyTerms t;
  for (int c = 0; c < kChannels; ++c) {
    t.motion += motion[c];
    t.detail += detail[c];
    AddChannelGradient(channels_[c].dya, c, d_a);
    AddChannelGradient(channels_[c].dyb, c, d_b);
  }
  if (terms) *terms = t;
  return scale * (options_.motion_weight * t.motion +
                  options_.detail_weight * t.detail);
}

void WaterEnergyLoss::EvaluateChannel(int c, const double* rendered_a,
                                      const double* rendered_b, int w, int h,
                                      double channel_scale,
                                      internal::ChannelScratch* s,
                                      double* motion, double* detail) const {
  const size_t pixels = static_cast<size_t>(w) * h;
  ChannelOf(rendered_a, pixels, c, &s->ya);
  ChannelOf(rendered_b, pixels, c, &s->yb);
  ChannelOf(input_a_.ptr<double>(), pixels, c, &s->ia);
  ChannelOf(input_b_.ptr<double>(), pixels, c, &s->ib);
  s->dya.assign(pixels, 0.0);
  s->dyb.assign(pixels, 0.0);
  *motion = *detail = 0;
  if (options_.motion_weight != 0) {
    s->diff.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) s->diff[p] = s->ib[p] - s->ia[p];
    Energy(s->diff, w, h, kernels_.window[0], &s->blur, &s->g, &s->e_i);
    for (size_t p = 0; p < pixels; ++p) s->diff[p] = s->yb[p] - s->ya[p];
    Energy(s->diff, w, h, kernels_.window[0], &s->blur, &s->g, &s->e_r);
    *motion = AmplitudeL1(s->e_r, s->e_i, mask_,
                          channel_scale * options_.motion_weight, &s->d_e) /
              kChannels;
    BlurAdjoint(s->d_e, w, h, kernels_.window[0], &s->blur, &s->g);
    for (size_t p = 0; p < pixels; ++p) {
      const double g = 2 * s->diff[p] * s->g[p];
      s->dyb[p] += g;
      s->dya[p] -= g;
    }
  }
  if (options_.detail_weight != 0) {
    const int octaves = options_.detail_octaves;
    const double band_scale =
        0.5 * channel_scale * options_.detail_weight / octaves;
    for (int f = 0; f < 2; ++f) {
      const std::vector<double>& y = f == 0 ? s->ya : s->yb;
      const std::vector<double>& input = f == 0 ? s->ia : s->ib;
      const std::vector<double>& water = f == 0 ? mask_a_ : mask_b_;
      std::vector<double>& dy = f == 0 ? s->dya : s->dyb;
      for (int k = 0; k < octaves; ++k) {
        const std::vector<double>& window = kernels_.window[k];
        Band(input, w, h, k, kernels_.detail, &s->blur, &s->low, &s->high);
        Energy(s->high, w, h, window, &s->blur, &s->g, &s->e_i);
        Band(y, w, h, k, kernels_.detail, &s->blur, &s->low, &s->high);
        Energy(s->high, w, h, window, &s->blur, &s->g, &s->e_r);
        *detail += 0.5 *
                   AmplitudeL1(s->e_r, s->e_i, water, band_scale, &s->d_e) /
                   (kChannels * octaves);
        BlurAdjoint(s->d_e, w, h, window, &s->blur, &s->g);
        for (size_t p = 0; p < pixels; ++p) s->g[p] *= 2 * s->high[p];
        AddBandAdjoint(s->g, w, h, k, kernels_.detail, &s->blur, &s->low,
                       &s->diff, &dy);
      }
    }
  }
}

}  // namespace es
