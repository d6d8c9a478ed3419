#include "costs/water_energy_loss.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

namespace es {
namespace {

constexpr int kChannels = 3;  // RGB, and the opponent channels

std::vector<double> GaussianKernel(double sigma) {
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

// One separable pass along x (step 1, n = width, lines = height) or y
// (step = width, n = height, lines = width), borders clamped:
//   out[i] = sum_j k[j] in[clamp(i + j - r)].
void Pass1d(const double* in, int n, int lines, int step, int line_step,
            const std::vector<double>& k, double* out) {
  const int r = static_cast<int>(k.size()) / 2;
  for (int l = 0; l < lines; ++l) {
    const double* src = in + static_cast<size_t>(l) * line_step;
    double* dst = out + static_cast<size_t>(l) * line_step;
    for (int i = 0; i < n; ++i) {
      double s = 0;
      for (int j = -r; j <= r; ++j)
        s += k[j + r] * src[static_cast<size_t>(
                            std::clamp(i + j, 0, n - 1)) * step];
      dst[static_cast<size_t>(i) * step] = s;
    }
  }
}

// The adjoint (transpose) of Pass1d: every input pixel gets back what it
// gave, borders included, so gradients are exact.
void Pass1dAdjoint(const double* g_out, int n, int lines, int step,
                   int line_step, const std::vector<double>& k,
                   double* g_in) {
  const int r = static_cast<int>(k.size()) / 2;
  for (int l = 0; l < lines; ++l) {
    const double* src = g_out + static_cast<size_t>(l) * line_step;
    double* dst = g_in + static_cast<size_t>(l) * line_step;
    for (int i = 0; i < n; ++i) dst[static_cast<size_t>(i) * step] = 0;
    for (int i = 0; i < n; ++i) {
      const double g = src[static_cast<size_t>(i) * step];
      for (int j = -r; j <= r; ++j)
        dst[static_cast<size_t>(std::clamp(i + j, 0, n - 1)) * step] +=
            k[j + r] * g;
    }
  }
}

// 2D blur (x pass, then y pass) and its adjoint (y, then x).
void Blur(const std::vector<double>& in, int w, int h,
          const std::vector<double>& k, std::vector<double>* tmp,
          std::vector<double>* out) {
  tmp->resize(in.size());
  out->resize(in.size());
  Pass1d(in.data(), w, h, 1, w, k, tmp->data());
  Pass1d(tmp->data(), h, w, w, 1, k, out->data());
}

void BlurAdjoint(const std::vector<double>& g_out, int w, int h,
                 const std::vector<double>& k, std::vector<double>* tmp,
                 std::vector<double>* g_in) {
  tmp->resize(g_out.size());
  g_in->resize(g_out.size());
  Pass1dAdjoint(g_out.data(), h, w, w, 1, k, tmp->data());
  Pass1dAdjoint(tmp->data(), w, h, 1, w, k, g_in->data());
}

// An orthonormal opponent colour basis: luminance, red-green,
// yellow-blue. Water's change and texture are mostly of luminance; in
// RGB, a render could match each channel's amplitude with a tint that
// flickers (red up while green goes down), which the chroma rows count.
constexpr double kOpponent[kChannels][kChannels] = {
    {0.57735026918962576, 0.57735026918962576, 0.57735026918962576},
    {0.70710678118654752, -0.70710678118654752, 0.0},
    {0.40824829046386302, 0.40824829046386302, -0.81649658092772603}};

// Opponent channel c of an H x W x 3 RGB image.
void ChannelOf(const double* rgb, size_t pixels, int c,
               std::vector<double>* out) {
  out->resize(pixels);
  const double* k = kOpponent[c];
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
  const double* k = kOpponent[c];
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

// High-pass y - G * y.
void HighPass(const std::vector<double>& y, int w, int h,
              const std::vector<double>& g, std::vector<double>* tmp,
              std::vector<double>* out) {
  Blur(y, w, h, g, tmp, out);
  for (size_t p = 0; p < y.size(); ++p) (*out)[p] = y[p] - (*out)[p];
}

// W * (x^2).
void Energy(const std::vector<double>& x, int w, int h,
            const std::vector<double>& window, std::vector<double>* tmp,
            std::vector<double>* square, std::vector<double>* out) {
  square->resize(x.size());
  for (size_t p = 0; p < x.size(); ++p) (*square)[p] = x[p] * x[p];
  Blur(*square, w, h, window, tmp, out);
}

}  // namespace

WaterEnergyLoss::WaterEnergyLoss(const WaterEnergyOptions& options)
    : options_(options),
      detail_kernel_(GaussianKernel(options.detail_sigma)),
      window_kernel_(GaussianKernel(options.window_sigma)) {
  CHECK_GT(options.eps, 0);
}

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
  WaterEnergyTerms t;
  for (int c = 0; c < kChannels; ++c) {
    ChannelOf(rendered_a, pixels, c, &ya_);
    ChannelOf(rendered_b, pixels, c, &yb_);
    ChannelOf(input_a_.ptr<double>(), pixels, c, &ia_);
    ChannelOf(input_b_.ptr<double>(), pixels, c, &ib_);
    dya_.assign(pixels, 0.0);
    dyb_.assign(pixels, 0.0);
    if (options_.motion_weight != 0) {
      diff_.resize(pixels);
      for (size_t p = 0; p < pixels; ++p) diff_[p] = ib_[p] - ia_[p];
      Energy(diff_, w, h, window_kernel_, &tmp_, &g_, &e_i_);
      for (size_t p = 0; p < pixels; ++p) diff_[p] = yb_[p] - ya_[p];
      Energy(diff_, w, h, window_kernel_, &tmp_, &g_, &e_r_);
      t.motion += AmplitudeL1(e_r_, e_i_, mask_,
                              channel_scale * options_.motion_weight, &d_e_) /
                  kChannels;
      BlurAdjoint(d_e_, w, h, window_kernel_, &tmp_, &g_);
      for (size_t p = 0; p < pixels; ++p) {
        const double g = 2 * diff_[p] * g_[p];
        dyb_[p] += g;
        dya_[p] -= g;
      }
    }
    if (options_.detail_weight != 0) {
      const double frame_scale = 0.5 * channel_scale * options_.detail_weight;
      for (int f = 0; f < 2; ++f) {
        const std::vector<double>& y = f == 0 ? ya_ : yb_;
        const std::vector<double>& input = f == 0 ? ia_ : ib_;
        const std::vector<double>& water = f == 0 ? mask_a_ : mask_b_;
        HighPass(input, w, h, detail_kernel_, &tmp_, &high_);
        Energy(high_, w, h, window_kernel_, &tmp_, &g_, &e_i_);
        HighPass(y, w, h, detail_kernel_, &tmp_, &high_);
        Energy(high_, w, h, window_kernel_, &tmp_, &g_, &e_r_);
        t.detail += 0.5 *
                    AmplitudeL1(e_r_, e_i_, water, frame_scale, &d_e_) /
                    kChannels;
        BlurAdjoint(d_e_, w, h, window_kernel_, &tmp_, &g_);
        for (size_t p = 0; p < pixels; ++p) g_[p] *= 2 * high_[p];
        // d (y - G y) = (I - G^T) applied to the high-pass gradient.
        BlurAdjoint(g_, w, h, detail_kernel_, &tmp_, &diff_);
        std::vector<double>& dy = f == 0 ? dya_ : dyb_;
        for (size_t p = 0; p < pixels; ++p) dy[p] += g_[p] - diff_[p];
      }
    }
    AddChannelGradient(dya_, c, d_a);
    AddChannelGradient(dyb_, c, d_b);
  }
  if (terms) *terms = t;
  return scale * (options_.motion_weight * t.motion +
                  options_.detail_weight * t.detail);
}

}  // namespace es
