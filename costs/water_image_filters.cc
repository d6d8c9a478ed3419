#include "costs/water_image_filters.h"

#include <utility>

#include <glog/logging.h>

#include "costs/water_energy_terms.h"
#include "costs/water_kernels.h"

namespace es {
namespace internal {
namespace {

// The scratch of a pass with kernel k over rows of w values.
WaterFilterScratch ScratchFor(const std::vector<double>& k, int w,
                              BlurScratch* tmp) {
  const size_t terms = k.size() * k.size();
  tmp->sources.resize(terms);
  tmp->coefficients.resize(terms);
  tmp->line.resize(w + k.size() - 1);
  return {tmp->sources.data(), tmp->coefficients.data(), tmp->line.data()};
}

}  // namespace

// x pass, then y pass; the adjoint y, then x.
void Blur(const std::vector<double>& in, int w, int h,
          const std::vector<double>& k, BlurScratch* tmp,
          std::vector<double>* out) {
  tmp->image.resize(in.size());
  out->resize(in.size());
  const WaterFilterScratch scratch = ScratchFor(k, w, tmp);
  const WaterKernelSet& kernels = WaterKernels();
  const int r = static_cast<int>(k.size()) / 2;
  kernels.blur_rows(in.data(), w, h, k.data(), r, scratch, tmp->image.data());
  kernels.blur_columns(tmp->image.data(), w, h, k.data(), r, scratch,
                       out->data());
}

void BlurAdjoint(const std::vector<double>& g_out, int w, int h,
                 const std::vector<double>& k, BlurScratch* tmp,
                 std::vector<double>* g_in) {
  tmp->image.resize(g_out.size());
  g_in->resize(g_out.size());
  const WaterFilterScratch scratch = ScratchFor(k, w, tmp);
  const WaterKernelSet& kernels = WaterKernels();
  const int r = static_cast<int>(k.size()) / 2;
  kernels.blur_columns_adjoint(g_out.data(), w, h, k.data(), r, scratch,
                               tmp->image.data());
  kernels.blur_rows_adjoint(tmp->image.data(), w, h, k.data(), r, scratch,
                            g_in->data());
}

void ChannelOf(const double* rgb, size_t pixels, int c,
               std::vector<double>* out) {
  out->resize(pixels);
  const double* k = kWaterOpponent[c];
  for (size_t p = 0; p < pixels; ++p) {
    const double* v = rgb + kWaterChannels * p;
    (*out)[p] = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  }
}

void AddChannelGradient(const std::vector<double>& d_channel, int c,
                        double* d_rgb) {
  if (d_rgb == nullptr) return;
  const double* k = kWaterOpponent[c];
  for (size_t p = 0; p < d_channel.size(); ++p) {
    double* d = d_rgb + kWaterChannels * p;
    d[0] += k[0] * d_channel[p];
    d[1] += k[1] * d_channel[p];
    d[2] += k[2] * d_channel[p];
  }
}

void WaterOf(const cv::Mat& mask, size_t pixels, std::vector<double>* out) {
  out->assign(pixels, 1.0);
  if (mask.empty()) return;
  CHECK(mask.type() == CV_32FC1 || mask.type() == CV_64FC1) << mask.type();
  CHECK_EQ(mask.total(), pixels);
  // Read in place (no converted copy per call): a float above 0.5 is one
  // whose double is.
  const cv::Mat m = mask.isContinuous() ? mask : mask.clone();
  if (m.type() == CV_32FC1) {
    const float* v = m.ptr<float>();
    for (size_t p = 0; p < pixels; ++p) (*out)[p] = v[p] > 0.5f ? 1.0 : 0.0;
  } else {
    const double* v = m.ptr<double>();
    for (size_t p = 0; p < pixels; ++p) (*out)[p] = v[p] > 0.5 ? 1.0 : 0.0;
  }
}

namespace {

// Band k with `blur` for every G: Blur gives the band, BlurAdjoint its
// adjoint (G_{k-1}^T - G_k^T) y.
template <typename BlurFn>
void BandWith(BlurFn blur, const std::vector<double>& y, int w, int h, int k,
              const std::vector<std::vector<double>>& kernels,
              BlurScratch* tmp, std::vector<double>* low,
              std::vector<double>* out) {
  const std::vector<double>* fine = &y;
  if (k > 0) {
    blur(y, w, h, kernels[k - 1], tmp, low);
    fine = low;
  }
  blur(y, w, h, kernels[k], tmp, out);
  for (size_t p = 0; p < y.size(); ++p) (*out)[p] = (*fine)[p] - (*out)[p];
}

}  // namespace

void Band(const std::vector<double>& y, int w, int h, int k,
          const std::vector<std::vector<double>>& kernels, BlurScratch* tmp,
          std::vector<double>* low, std::vector<double>* out) {
  BandWith(Blur, y, w, h, k, kernels, tmp, low, out);
}

void Bands(const std::vector<double>& y, int w, int h, int count,
           const std::vector<std::vector<double>>& kernels, BlurScratch* tmp,
           std::vector<double>* low, std::vector<double>* next,
           std::vector<double>* out) {
  for (int k = 0; k < count; ++k) {
    const std::vector<double>& fine = k == 0 ? y : *low;
    Blur(y, w, h, kernels[k], tmp, next);
    std::vector<double>& band = out[k];
    band.resize(y.size());
    for (size_t p = 0; p < y.size(); ++p) band[p] = fine[p] - (*next)[p];
    std::swap(*low, *next);
  }
}

void AddBandAdjoint(const std::vector<double>& g, int w, int h, int k,
                    const std::vector<std::vector<double>>& kernels,
                    BlurScratch* tmp, std::vector<double>* low,
                    std::vector<double>* coarse, std::vector<double>* dy) {
  BandWith(BlurAdjoint, g, w, h, k, kernels, tmp, low, coarse);
  for (size_t p = 0; p < g.size(); ++p) (*dy)[p] += (*coarse)[p];
}

}  // namespace internal
}  // namespace es
