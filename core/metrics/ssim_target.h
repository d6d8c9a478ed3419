#ifndef EULERSPLAT_CORE_METRICS_SSIM_TARGET_H_
#define EULERSPLAT_CORE_METRICS_SSIM_TARGET_H_

// SSIM (the window and constants of core/metrics/ssim_kernels.h) of a
// rendering against a target whose window statistics are computed once and
// can be kept (SsimTarget), in precision T, on plain arrays: no OpenCV, so
// the CUDA backend's checks can use it as the CPU twin. core/metrics/ssim.h
// adds the cv::Mat entry point.

#include <cstddef>
#include <vector>

#include "core/metrics/ssim_kernels.h"

namespace es {

// The window's statistics of one target image (H x W x C).
template <typename T>
struct SsimTarget {
  int rows = 0, cols = 0, channels = 0;
  // The image: the target's own pixels when they are already T (the target
  // must then outlive these statistics), else `converted`.
  const T* y = nullptr;
  std::vector<T> converted;
  std::vector<T> mu, var;  // G * y and G * y^2 - mu^2

  size_t bytes() const {
    return (converted.size() + mu.size() + var.size()) * sizeof(T);
  }
};

// SSIM's scratch buffers, kept between calls (reallocated only when the
// image size or thread count changes). Not thread-safe.
template <typename T>
class SsimScratch {
 public:
  explicit SsimScratch(SimdLevel level = SimdLevel::kAuto) : level_(level) {}

  // A pass over rows x cols x channels images, pointing at this scratch.
  SsimPass<T> Prepare(int rows, int cols, int channels);
  const SsimKernelSet<T>& kernels() const;

 private:
  SimdLevel level_;
  int rows_ = 0, cols_ = 0, channels_ = 0, threads_ = 0;
  std::vector<T> planes_, grad_terms_, thread_rows_, zero_row_;
  std::vector<double> row_sums_;
};

// Fills *target from y (rows x cols x channels, interleaved, in T; y must
// outlive the statistics).
template <typename T>
void ComputeSsimTarget(const T* y, int rows, int cols, int channels,
                       SsimScratch<T>* scratch, SsimTarget<T>* target);

// Mean SSIM of x (target-sized, interleaved doubles) against the target.
// If d_x is not null it receives grad_scale * d mean SSIM / d x; if map is
// not null, the per-value SSIM.
template <typename T>
double SsimAgainstTarget(const double* x, const SsimTarget<T>& target,
                         SsimScratch<T>* scratch, double grad_scale = 1,
                         double* d_x = nullptr, double* map = nullptr);

// The photometric loss's two terms in one sweep: returns mean SSIM and sets
// *l1 to mean |x - y| (computed in T); d_x (nullable) receives
// ssim_grad_scale * d SSIM / dx + l1_grad_scale * d L1 / dx.
template <typename T>
double SsimAndL1AgainstTarget(const double* x, const SsimTarget<T>& target,
                              SsimScratch<T>* scratch, double ssim_grad_scale,
                              double l1_grad_scale, double* d_x, double* l1);

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_SSIM_TARGET_H_
