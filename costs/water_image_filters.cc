#include "costs/water_image_filters.h"

#include <algorithm>
#include <utility>

#include <glog/logging.h>

#include "costs/water_energy_terms.h"

namespace es {
namespace internal {
namespace {

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

}  // namespace

// x pass, then y pass; the adjoint y, then x.
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
