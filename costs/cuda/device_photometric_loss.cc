#include "costs/cuda/device_photometric_loss.h"

#include <glog/logging.h>

#include <cmath>

#include "core/metrics/ssim_kernels.h"
#include "costs/cuda/photometric_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kChannels = 3;

// The CPU's window (WindowWeights in core/metrics/ssim_target.cc): the
// Gaussian in double, normalized over its 11 taps, then rounded to float.
SsimWindow Window() {
  double g[kSsimRadius + 1], sum = 0;
  for (int k = 0; k <= kSsimRadius; ++k) {
    g[k] = std::exp(-k * k / (2 * kSsimSigma * kSsimSigma));
    sum += k == 0 ? g[k] : 2 * g[k];
  }
  SsimWindow w;
  for (int k = 0; k <= kSsimRadius; ++k)
    w.w[k] = static_cast<float>(g[k] / sum);
  return w;
}

}  // namespace

DevicePhotometricLoss::DevicePhotometricLoss(double ssim_weight)
    : ssim_weight_(ssim_weight) {}

double DevicePhotometricLoss::Evaluate(const float* rendered,
                                       const float* target, int width,
                                       int height, double scale,
                                       float* d_rendered) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  const int row_len = width * kChannels;
  const long long n = static_cast<long long>(height) * row_len;
  const double a = scale * (1 - ssim_weight_);
  const int blocks = PhotometricBlocks(n);
  partials_.Resize(2 * static_cast<size_t>(blocks));
  sums_.Resize(2);
  if (ssim_weight_ != 0) {
    // As the CPU fuses it: SSIM's terms, then the gradient of both.
    const SsimWindow window = Window();
    planes_.Resize(5 * n);
    scratch_.Resize(5 * n);
    blurred_.Resize(5 * n);
    SsimProducts(n, rendered, target, planes_.data());
    SsimBlur(5, height, row_len, kChannels, window, planes_.data(),
             scratch_.data(), blurred_.data());
    float* terms = d_rendered != nullptr ? planes_.data() : nullptr;
    SsimTerms(n, blurred_.data(), rendered, target, terms, partials_.data());
    if (d_rendered != nullptr) {
      SsimBlur(3, height, row_len, kChannels, window, terms, scratch_.data(),
               blurred_.data());
      SsimGradient(n, blurred_.data(), rendered, target,
                   -scale * ssim_weight_, a / static_cast<double>(n),
                   d_rendered);
    }
  } else {
    L1Terms(n, rendered, target, a * (1.0 / static_cast<double>(n)),
            d_rendered, partials_.data());
  }
  SumPartials(blocks, partials_.data(), sums_.data());
  double sums[2];
  sums_.Download(sums);
  ssim_ = ssim_weight_ != 0 ? sums[0] / static_cast<double>(n) : 1.0;
  l1_ = sums[1] / static_cast<double>(n);
  return (1 - ssim_weight_) * l1_ + ssim_weight_ * (1 - ssim_);
}

}  // namespace cuda
}  // namespace es
