#include "core/metrics/ssim_target.h"

#include <glog/logging.h>
#include <omp.h>

#include <cmath>

namespace es {
namespace {

// Below this many values a pass runs on the calling thread only (tests,
// thumbnails): OpenMP's start-up would cost more than the blurs.
constexpr size_t kMinParallelValues = 1 << 14;

// The 1D window, centre tap first, normalized as its 11 taps sum to 1.
template <typename T>
void WindowWeights(T* w) {
  double g[kSsimRadius + 1], sum = 0;
  for (int k = 0; k <= kSsimRadius; ++k) {
    g[k] = std::exp(-k * k / (2 * kSsimSigma * kSsimSigma));
    sum += k == 0 ? g[k] : 2 * g[k];
  }
  for (int k = 0; k <= kSsimRadius; ++k) w[k] = static_cast<T>(g[k] / sum);
}

}  // namespace

template <>
const SsimKernelSet<float>& SsimKernels<float>(SimdLevel level) {
  return ForSimdLevel(level, &ssim_sse2::FloatKernels,
                      &ssim_avx2::FloatKernels,
                      &ssim_avx512::FloatKernels)();
}

template <>
const SsimKernelSet<double>& SsimKernels<double>(SimdLevel level) {
  return ForSimdLevel(level, &ssim_sse2::DoubleKernels,
                      &ssim_avx2::DoubleKernels,
                      &ssim_avx512::DoubleKernels)();
}

template <typename T>
const SsimKernelSet<T>& SsimScratch<T>::kernels() const {
  return SsimKernels<T>(level_);
}

template <typename T>
SsimPass<T> SsimScratch<T>::Prepare(int rows, int cols, int channels) {
  CHECK_GT(rows, 0);
  CHECK_GT(cols, 0);
  CHECK_GT(channels, 0);
  const int row_len = cols * channels;
  const int padded_len = row_len + 2 * kSsimRadius * channels;
  const int threads = omp_get_max_threads();
  const size_t n = static_cast<size_t>(rows) * row_len;
  const long long thread_stride = 3LL * padded_len + 3LL * row_len;
  if (rows != rows_ || cols != cols_ || channels != channels_ ||
      threads > threads_) {
    // The kernels rely on zero row margins, which they never write.
    planes_.assign(3 * n, T(0));
    grad_terms_.assign(3 * static_cast<size_t>(rows) * padded_len, T(0));
    thread_rows_.assign(thread_stride * threads, T(0));
    zero_row_.assign(row_len, T(0));
    row_sums_.assign(2 * static_cast<size_t>(rows), 0.0);
    rows_ = rows, cols_ = cols, channels_ = channels, threads_ = threads;
  }
  SsimPass<T> p;
  p.rows = rows;
  p.row_len = row_len;
  p.channels = channels;
  WindowWeights(p.weights);
  p.planes = planes_.data();
  p.grad_terms = grad_terms_.data();
  p.thread_rows = thread_rows_.data();
  p.thread_stride = thread_stride;
  p.zero_row = zero_row_.data();
  p.row_sums = row_sums_.data();
  p.parallel = n >= kMinParallelValues;
  return p;
}

template <typename T>
void ComputeSsimTarget(const T* y, int rows, int cols, int channels,
                       SsimScratch<T>* scratch, SsimTarget<T>* target) {
  target->rows = rows;
  target->cols = cols;
  target->channels = channels;
  if (y != target->converted.data()) target->converted.clear();
  target->y = y;
  const size_t n = static_cast<size_t>(rows) * cols * channels;
  target->mu.resize(n);
  target->var.resize(n);
  SsimPass<T> p = scratch->Prepare(rows, cols, channels);
  p.y = y;
  scratch->kernels().target_stats(p, target->mu.data(), target->var.data());
}

namespace {

template <typename T>
SsimPass<T> PassAgainst(const double* x, const SsimTarget<T>& target,
                        SsimScratch<T>* scratch) {
  SsimPass<T> p = scratch->Prepare(target.rows, target.cols, target.channels);
  p.x = x;
  p.y = target.y;
  p.mu_y = target.mu.data();
  p.var_y = target.var.data();
  return p;
}

}  // namespace

template <typename T>
double SsimAgainstTarget(const double* x, const SsimTarget<T>& target,
                         SsimScratch<T>* scratch, double grad_scale,
                         double* d_x, double* map) {
  SsimPass<T> p = PassAgainst(x, target, scratch);
  p.map = map;
  p.d_x = d_x;
  p.grad_scale = grad_scale;
  return scratch->kernels().evaluate(p);
}

template <typename T>
double SsimAndL1AgainstTarget(const double* x, const SsimTarget<T>& target,
                              SsimScratch<T>* scratch, double ssim_grad_scale,
                              double l1_grad_scale, double* d_x, double* l1) {
  CHECK(l1 != nullptr);
  SsimPass<T> p = PassAgainst(x, target, scratch);
  p.d_x = d_x;
  p.grad_scale = ssim_grad_scale;
  p.l1 = l1;
  p.l1_grad_scale = l1_grad_scale;
  return scratch->kernels().evaluate(p);
}

#define ES_INSTANTIATE_SSIM(T)                                            \
  template class SsimScratch<T>;                                          \
  template void ComputeSsimTarget(const T*, int, int, int, SsimScratch<T>*, \
                                  SsimTarget<T>*);                        \
  template double SsimAgainstTarget(const double*, const SsimTarget<T>&,  \
                                    SsimScratch<T>*, double, double*,     \
                                    double*);                             \
  template double SsimAndL1AgainstTarget(                                 \
      const double*, const SsimTarget<T>&, SsimScratch<T>*, double, double, \
      double*, double*);
ES_INSTANTIATE_SSIM(float)
ES_INSTANTIATE_SSIM(double)
#undef ES_INSTANTIATE_SSIM

}  // namespace es
