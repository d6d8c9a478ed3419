#include "core/metrics/image_metrics.h"

#include <glog/logging.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace es {
namespace {

// Zero-padded 'same' Gaussian filtering into dst (reusing its memory). The
// kernel is symmetric and the padding is zero, so this filter is its own
// adjoint (used by the gradient).
void Blur(const cv::Mat& src, cv::Mat* dst) {
  static const cv::Mat kernel =
      cv::getGaussianKernel(kSsimWindow, kSsimSigma, CV_64F);
  cv::sepFilter2D(src, *dst, CV_64F, kernel, kernel, cv::Point(-1, -1), 0,
                  cv::BORDER_CONSTANT);
}

void CheckPair(const cv::Mat& x, const cv::Mat& y) {
  CHECK_EQ(x.depth(), CV_64F);
  CHECK_EQ(x.type(), y.type());
  CHECK(x.size() == y.size());
  CHECK(x.isContinuous() && y.isContinuous());
}

// Fills ws->mu_x, mu_y, s_xx, s_yy, s_xy: everything SSIM's value and
// gradient need, per pixel and channel.
void ComputeTerms(const cv::Mat& x, const cv::Mat& y, SsimWorkspace* ws) {
  const size_t n = x.total() * x.channels();
  ws->xx.create(x.size(), x.type());
  ws->yy.create(x.size(), x.type());
  ws->xy.create(x.size(), x.type());
  const double* px = x.ptr<double>();
  const double* py = y.ptr<double>();
  double* pxx = ws->xx.ptr<double>();
  double* pyy = ws->yy.ptr<double>();
  double* pxy = ws->xy.ptr<double>();
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) {
    pxx[i] = px[i] * px[i];
    pyy[i] = py[i] * py[i];
    pxy[i] = px[i] * py[i];
  }
  Blur(x, &ws->mu_x);
  Blur(y, &ws->mu_y);
  Blur(ws->xx, &ws->s_xx);
  Blur(ws->yy, &ws->s_yy);
  Blur(ws->xy, &ws->s_xy);
  const double* mx = ws->mu_x.ptr<double>();
  const double* my = ws->mu_y.ptr<double>();
  double* sxx = ws->s_xx.ptr<double>();
  double* syy = ws->s_yy.ptr<double>();
  double* sxy = ws->s_xy.ptr<double>();
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) {
    sxx[i] -= mx[i] * mx[i];
    syy[i] -= my[i] * my[i];
    sxy[i] -= mx[i] * my[i];
  }
}

double MaskedMean(const cv::Mat& values, const cv::Mat& mask, bool invert) {
  CHECK(mask.size() == values.size());
  cv::Mat m;
  mask.convertTo(m, CV_64F);
  const int channels = values.channels();
  double sum = 0;
  int64_t count = 0;
  for (int i = 0; i < values.rows; ++i) {
    const double* v = values.ptr<double>(i);
    const double* mi = m.ptr<double>(i);
    for (int j = 0; j < values.cols; ++j) {
      if ((mi[j] > 0.5) == invert) continue;
      for (int c = 0; c < channels; ++c) sum += v[j * channels + c];
      count += channels;
    }
  }
  return count ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

double PsnrFromMse(double mse) {
  if (std::isnan(mse)) return mse;
  return mse > 1e-10 ? -10.0 * std::log10(mse) : 100.0;
}

}  // namespace

double L1Loss(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x) {
  CheckPair(x, y);
  const size_t n = x.total() * x.channels();
  const double* px = x.ptr<double>();
  const double* py = y.ptr<double>();
  double* pd = nullptr;
  if (d_x) {
    d_x->create(x.size(), x.type());
    pd = d_x->ptr<double>();
  }
  const double inv_n = 1.0 / n;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double diff = px[i] - py[i];
    sum += std::abs(diff);
    if (pd) pd[i] = diff > 0 ? inv_n : (diff < 0 ? -inv_n : 0.0);
  }
  return sum * inv_n;
}

cv::Mat SsimMap(const cv::Mat& x, const cv::Mat& y) {
  CheckPair(x, y);
  SsimWorkspace ws;
  ComputeTerms(x, y, &ws);
  const SsimWorkspace& t = ws;
  cv::Mat map(x.size(), x.type());
  const size_t n = x.total() * x.channels();
  const double* mx = t.mu_x.ptr<double>();
  const double* my = t.mu_y.ptr<double>();
  const double* sxx = t.s_xx.ptr<double>();
  const double* syy = t.s_yy.ptr<double>();
  const double* sxy = t.s_xy.ptr<double>();
  double* out = map.ptr<double>();
  for (size_t i = 0; i < n; ++i) {
    out[i] = (2 * mx[i] * my[i] + kSsimC1) * (2 * sxy[i] + kSsimC2) /
             ((mx[i] * mx[i] + my[i] * my[i] + kSsimC1) *
              (sxx[i] + syy[i] + kSsimC2));
  }
  return map;
}

double Ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x) {
  SsimWorkspace ws;
  return Ssim(x, y, d_x, &ws);
}

double Ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x,
            SsimWorkspace* ws) {
  CheckPair(x, y);
  ComputeTerms(x, y, ws);
  const SsimWorkspace& t = *ws;
  const size_t n = x.total() * x.channels();
  const double* mx = t.mu_x.ptr<double>();
  const double* my = t.mu_y.ptr<double>();
  const double* sxx = t.s_xx.ptr<double>();
  const double* syy = t.s_yy.ptr<double>();
  const double* sxy = t.s_xy.ptr<double>();
  // d S / d (mu_x, E[x^2], E[xy]) per pixel, then pulled back through the
  // (self-adjoint) window: d/dx = G*a + 2 x G*b + y G*c.
  double *pa = nullptr, *pb = nullptr, *pc = nullptr;
  if (d_x) {
    ws->a.create(x.size(), x.type());
    ws->b.create(x.size(), x.type());
    ws->c.create(x.size(), x.type());
    pa = ws->a.ptr<double>();
    pb = ws->b.ptr<double>();
    pc = ws->c.ptr<double>();
  }
  const double inv_n = 1.0 / n;
  const bool want_grad = d_x != nullptr;
  double sum = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (size_t i = 0; i < n; ++i) {
    const double a1 = 2 * mx[i] * my[i] + kSsimC1;
    const double a2 = 2 * sxy[i] + kSsimC2;
    const double b1 = mx[i] * mx[i] + my[i] * my[i] + kSsimC1;
    const double b2 = sxx[i] + syy[i] + kSsimC2;
    const double s = a1 * a2 / (b1 * b2);
    sum += s;
    if (!want_grad) continue;
    const double ds_dsxx = -s / b2;
    const double ds_dsxy = 2 * a1 / (b1 * b2);
    const double ds_dmx = 2 * my[i] * a2 / (b1 * b2) - 2 * mx[i] * s / b1;
    pa[i] = (ds_dmx - 2 * mx[i] * ds_dsxx - my[i] * ds_dsxy) * inv_n;
    pb[i] = ds_dsxx * inv_n;
    pc[i] = ds_dsxy * inv_n;
  }
  if (d_x) {
    // The blurs of a, b, c reuse the buffers of E[x^2], E[y^2], E[xy].
    Blur(ws->a, &ws->xx);
    Blur(ws->b, &ws->yy);
    Blur(ws->c, &ws->xy);
    d_x->create(x.size(), x.type());
    double* pd = d_x->ptr<double>();
    const double* px = x.ptr<double>();
    const double* py = y.ptr<double>();
    const double* qa = ws->xx.ptr<double>();
    const double* qb = ws->yy.ptr<double>();
    const double* qc = ws->xy.ptr<double>();
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i)
      pd[i] = qa[i] + 2 * px[i] * qb[i] + py[i] * qc[i];
  }
  return sum * inv_n;
}

double Psnr(const cv::Mat& x, const cv::Mat& y) {
  CheckPair(x, y);
  const cv::Mat diff = x - y;
  const double mse = diff.dot(diff) / (x.total() * x.channels());
  return PsnrFromMse(mse);
}

double MaskedPsnr(const cv::Mat& x, const cv::Mat& y, const cv::Mat& mask,
                  bool invert) {
  CheckPair(x, y);
  const cv::Mat diff = x - y;
  return PsnrFromMse(MaskedMean(diff.mul(diff), mask, invert));
}

double MaskedSsim(const cv::Mat& x, const cv::Mat& y, const cv::Mat& mask,
                  bool invert) {
  return MaskedMean(SsimMap(x, y), mask, invert);
}

}  // namespace es
