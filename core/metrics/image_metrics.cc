#include "core/metrics/image_metrics.h"

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

#include "core/metrics/ssim.h"

namespace es {
namespace {

void CheckPair(const cv::Mat& x, const cv::Mat& y) {
  CHECK_EQ(x.depth(), CV_64F);
  CHECK_EQ(x.type(), y.type());
  CHECK(x.size() == y.size());
  CHECK(x.isContinuous() && y.isContinuous());
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

namespace {

// Each thread's SSIM buffers, kept between calls (their size is that of
// the last image scored): an evaluation scores many frames of one size,
// and fresh buffers cost their allocation, their zeroing and a page fault
// per page at every call.
struct SsimBuffers {
  SsimScratch<double> scratch;
  SsimTarget<double> target;
};
SsimBuffers& ThreadSsimBuffers() {
  thread_local SsimBuffers buffers;
  return buffers;
}

}  // namespace

cv::Mat SsimMap(const cv::Mat& x, const cv::Mat& y) {
  CheckPair(x, y);
  SsimBuffers& b = ThreadSsimBuffers();
  ComputeSsimTarget(y, &b.scratch, &b.target);
  cv::Mat map(x.size(), x.type());
  SsimAgainstTarget(x.ptr<double>(), b.target, &b.scratch, 1.0, nullptr,
                    map.ptr<double>());
  return map;
}

double Ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* d_x) {
  CheckPair(x, y);
  SsimBuffers& b = ThreadSsimBuffers();
  SsimScratch<double>& scratch = b.scratch;
  SsimTarget<double>& target = b.target;
  ComputeSsimTarget(y, &scratch, &target);
  double* grad = nullptr;
  if (d_x) {
    d_x->create(x.size(), x.type());
    grad = d_x->ptr<double>();
  }
  return SsimAgainstTarget(x.ptr<double>(), target, &scratch, 1.0, grad);
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

cv::Mat FarFromMask(const cv::Mat& mask, double distance) {
  cv::Mat m;
  mask.convertTo(m, CV_64F);
  const cv::Mat water = m > 0.5;
  if (cv::countNonZero(water) == 0) {
    return cv::Mat::ones(mask.size(), CV_64FC1);
  }
  // distanceTransform measures to the nearest zero: the water pixels.
  cv::Mat to_water;
  cv::distanceTransform(~water, to_water, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::Mat far;
  cv::Mat(to_water > distance).convertTo(far, CV_64F, 1.0 / 255);
  return far;
}

}  // namespace es
