#include "costs/water_energy_loss.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

#include "core/base/stage_profile.h"
#include "costs/water_kernels.h"

namespace es {
namespace {

using internal::AddBandAdjoint;
using internal::AddChannelGradient;
using internal::Band;
using internal::Blur;
using internal::BlurAdjoint;
using internal::BlurScratch;
using internal::ChannelOf;
using internal::WaterOf;

constexpr int kChannels = internal::kWaterChannels;

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
    : options_(options),
      kernels_(MakeWaterEnergyKernels(options)),
      motion_floors_(RenderedEnergyFloors(options, kernels_, -1)),
      motion_inputs_(options.input_cache_bytes / 2),
      detail_inputs_(options.input_cache_bytes / 2) {
  for (int k = 0; k < options.detail_octaves; ++k)
    band_floors_.push_back(RenderedEnergyFloors(options, kernels_, k));
}

double WaterEnergyLoss::AmplitudeL1(const std::vector<double>& e_rendered,
                                    const std::vector<double>& e_input,
                                    const std::vector<double>& mask,
                                    double floor, double scale,
                                    std::vector<double>* term,
                                    std::vector<double>* d_energy) const {
  double count = 0;
  for (double m : mask) count += m;
  d_energy->resize(mask.size());
  term->resize(mask.size());
  if (count == 0) {
    std::fill(d_energy->begin(), d_energy->end(), 0.0);
    return 0;
  }
  WaterKernels().amplitude_terms(
      e_rendered.data(), e_input.data(), mask.data(),
      static_cast<long>(mask.size()), floor, options_.eps, scale, count,
      term->data(), d_energy->data());
  // Summed in pixel order, as one thread would: the same bits on every
  // CPU.
  double sum = 0;
  for (double t : *term) sum += t;
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
  // The inputs' energies, each computed once while the cache has room.
  const size_t channel_bytes = kChannels * pixels * sizeof(double);
  const internal::InputEnergies* motion_in = nullptr;
  const internal::InputEnergies* detail_in[2] = {nullptr, nullptr};
  if (options_.motion_weight != 0) {
    motion_in = &motion_inputs_.Get(
        {&input_a, &input_b}, channel_bytes,
        [&](internal::InputEnergies* e) { MotionInputs(input_a, input_b, e); });
  }
  if (options_.detail_weight != 0) {
    const size_t bytes = options_.detail_octaves * channel_bytes;
    detail_in[0] = &detail_inputs_.Get(
        {&input_a}, bytes,
        [&](internal::InputEnergies* e) { DetailInputs(input_a, e); });
    detail_in[1] = &detail_inputs_.Get(
        {&input_b}, bytes,
        [&](internal::InputEnergies* e) { DetailInputs(input_b, e); },
        &detail_b_spare_);
  }
  WaterOf(mask_a, pixels, &mask_a_);
  WaterOf(mask_b, pixels, &mask_b_);
  mask_.resize(pixels);
  for (size_t p = 0; p < pixels; ++p)
    mask_[p] = std::max(mask_a_[p], mask_b_[p]);

  // Each opponent channel on its own, averaged: a change of hue that the
  // input does not have is not counted as the input's change. Each
  // channel's terms run as three tasks (the motion, frame A's detail and
  // frame B's), each into its own gradients, added up after in the order
  // one task after another would have.
  const double channel_scale = scale / kChannels;
  // (Small images on one thread: there the fork costs more than it saves.)
  const bool parallel = pixels >= 16384;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (int c = 0; c < kChannels; ++c) {
    ChannelOf(rendered_a, pixels, c, &channels_[c].ya);
    ChannelOf(rendered_b, pixels, c, &channels_[c].yb);
  }
  std::array<double, kChannels> motion{}, detail[2] = {};
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (int task = 0; task < 3 * kChannels; ++task) {
    const int c = task / 3, part = task % 3;
    internal::ChannelScratch& s = channels_[c];
    internal::TermScratch& scratch = s.terms[part];
    scratch.dya.assign(part == 2 ? 0 : pixels, 0.0);
    scratch.dyb.assign(part == 1 ? 0 : pixels, 0.0);
    if (part == 0 && motion_in != nullptr) {
      motion[c] = MotionTerm(c, s.ya, s.yb, w, h, channel_scale,
                             motion_in->energies[c][0], &scratch);
    } else if (part > 0 && detail_in[0] != nullptr) {
      const int f = part - 1;
      detail[f][c] = DetailTerm(c, f == 0 ? s.ya : s.yb, w, h, channel_scale,
                                detail_in[f]->energies[c],
                                f == 0 ? mask_a_ : mask_b_,
                                f == 0 ? &scratch.dya : &scratch.dyb,
                                &scratch);
    }
  }
  WaterEnergyTerms t;
  for (int c = 0; c < kChannels; ++c) {
    t.motion += motion[c];
    t.detail += detail[0][c] + detail[1][c];
    // The motion's gradients, then each frame's detail added to them.
    std::array<internal::TermScratch, 3>& parts = channels_[c].terms;
    for (size_t p = 0; p < pixels; ++p) {
      parts[0].dya[p] += parts[1].dya[p];
      parts[0].dyb[p] += parts[2].dyb[p];
    }
    AddChannelGradient(parts[0].dya, c, d_a);
    AddChannelGradient(parts[0].dyb, c, d_b);
  }
  if (terms) *terms = t;
  return scale * (options_.motion_weight * t.motion +
                  options_.detail_weight * t.detail);
}

void WaterEnergyLoss::MotionInputs(const cv::Mat& input_a,
                                   const cv::Mat& input_b,
                                   internal::InputEnergies* out) {
  const int w = input_a.cols, h = input_a.rows;
  const size_t pixels = static_cast<size_t>(w) * h;
  input_a.convertTo(input_a_, CV_64FC3);
  input_b.convertTo(input_b_, CV_64FC3);
  // Scratch: the renders' are not taken yet.
  std::vector<double>& ia = channels_[0].ya;
  std::vector<double>& ib = channels_[0].yb;
  internal::TermScratch& s = channels_[0].terms[0];
  for (int c = 0; c < kChannels; ++c) {
    ChannelOf(input_a_.ptr<double>(), pixels, c, &ia);
    ChannelOf(input_b_.ptr<double>(), pixels, c, &ib);
    s.diff.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) s.diff[p] = ib[p] - ia[p];
    out->energies[c].resize(1);
    Energy(s.diff, w, h, kernels_.window[0], &s.blur, &s.g,
           &out->energies[c][0]);
  }
}

void WaterEnergyLoss::DetailInputs(const cv::Mat& input,
                                   internal::InputEnergies* out) {
  const int w = input.cols, h = input.rows;
  const size_t pixels = static_cast<size_t>(w) * h;
  input.convertTo(input_a_, CV_64FC3);
  // Scratch: the renders' are not taken yet.
  std::vector<double>& y = channels_[0].ya;
  internal::TermScratch& s = channels_[0].terms[0];
  for (int c = 0; c < kChannels; ++c) {
    ChannelOf(input_a_.ptr<double>(), pixels, c, &y);
    out->energies[c].resize(options_.detail_octaves);
    for (int k = 0; k < options_.detail_octaves; ++k) {
      Band(y, w, h, k, kernels_.detail, &s.blur, &s.low, &s.high);
      Energy(s.high, w, h, kernels_.window[k], &s.blur, &s.g,
             &out->energies[c][k]);
    }
  }
}

double WaterEnergyLoss::MotionTerm(int c, const std::vector<double>& ya,
                                   const std::vector<double>& yb, int w,
                                   int h, double channel_scale,
                                   const std::vector<double>& e_input,
                                   internal::TermScratch* s) const {
  const size_t pixels = static_cast<size_t>(w) * h;
  s->diff.resize(pixels);
  for (size_t p = 0; p < pixels; ++p) s->diff[p] = yb[p] - ya[p];
  Energy(s->diff, w, h, kernels_.window[0], &s->blur, &s->g, &s->e_r);
  const double motion =
      AmplitudeL1(s->e_r, e_input, mask_, motion_floors_[c],
                  channel_scale * options_.motion_weight, &s->term, &s->d_e) /
      kChannels;
  BlurAdjoint(s->d_e, w, h, kernels_.window[0], &s->blur, &s->g);
  for (size_t p = 0; p < pixels; ++p) {
    const double g = 2 * s->diff[p] * s->g[p];
    s->dyb[p] += g;
    s->dya[p] -= g;
  }
  return motion;
}

double WaterEnergyLoss::DetailTerm(
    int c, const std::vector<double>& y, int w, int h, double channel_scale,
    const std::vector<std::vector<double>>& e_input,
    const std::vector<double>& water, std::vector<double>* dy,
    internal::TermScratch* s) const {
  const size_t pixels = static_cast<size_t>(w) * h;
  const int octaves = options_.detail_octaves;
  const double band_scale =
      0.5 * channel_scale * options_.detail_weight / octaves;
  double detail = 0;
  for (int k = 0; k < octaves; ++k) {
    const std::vector<double>& window = kernels_.window[k];
    Band(y, w, h, k, kernels_.detail, &s->blur, &s->low, &s->high);
    Energy(s->high, w, h, window, &s->blur, &s->g, &s->e_r);
    detail += 0.5 *
              AmplitudeL1(s->e_r, e_input[k], water, band_floors_[k][c],
                          band_scale, &s->term, &s->d_e) /
              (kChannels * octaves);
    BlurAdjoint(s->d_e, w, h, window, &s->blur, &s->g);
    for (size_t p = 0; p < pixels; ++p) s->g[p] *= 2 * s->high[p];
    AddBandAdjoint(s->g, w, h, k, kernels_.detail, &s->blur, &s->low,
                   &s->diff, dy);
  }
  return detail;
}

}  // namespace es
