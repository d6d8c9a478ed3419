// SSIM's blurs and per-pixel terms. Included only by
// ssim_kernels_{sse2,avx2,avx512}.cc, each compiled for its instruction set
// with ES_SSIM_ISA naming its namespace. Everything here has internal
// linkage and calls no out-of-line library code (OpenMP's runtime aside),
// so no function compiled for AVX2 / AVX-512 can be merged into, or called
// from, code that runs on a CPU without it.
//
// Each blur runs in two passes over rows with contiguous inner loops and no
// per-pixel branch: along rows from a zero-padded copy of the row, then
// down columns from eleven row pointers (rows outside the image point at a
// row of zeros). The per-pixel work is fused into the passes: the products
// x^2 and x y are formed while a row is padded, and SSIM, its gradient
// terms and the final d/dx are computed while a column-blurred row is still
// in L1.

#if !defined(ES_SSIM_ISA)
#error "define ES_SSIM_ISA before this header"
#endif

#include <omp.h>

#include <cstddef>

#include "core/metrics/ssim_kernels.h"

namespace es {
namespace ES_SSIM_ISA {
namespace {

constexpr int kR = kSsimRadius;
constexpr int kMaxPlanes = 3;

// out[j] = sum_k w_|k| p[j + k c] for |k| <= 5 (p has 5 c zeros on both
// sides).
template <typename T>
void BlurRow(const T* __restrict p, int n, int c, const T* w,
             T* __restrict out) {
  const T w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3], w4 = w[4], w5 = w[5];
  const int c2 = 2 * c, c3 = 3 * c, c4 = 4 * c, c5 = 5 * c;
  for (int j = 0; j < n; ++j) {
    out[j] = w0 * p[j] + w1 * (p[j - c] + p[j + c]) +
             w2 * (p[j - c2] + p[j + c2]) + w3 * (p[j - c3] + p[j + c3]) +
             w4 * (p[j - c4] + p[j + c4]) + w5 * (p[j - c5] + p[j + c5]);
  }
}

// out[j] = sum_k w_|k| row_k[j] over the eleven rows centred on q0.
template <typename T>
void BlurColumn(const T* __restrict q0, const T* __restrict m1,
                const T* __restrict p1, const T* __restrict m2,
                const T* __restrict p2, const T* __restrict m3,
                const T* __restrict p3, const T* __restrict m4,
                const T* __restrict p4, const T* __restrict m5,
                const T* __restrict p5, int n, const T* w,
                T* __restrict out) {
  const T w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3], w4 = w[4], w5 = w[5];
  for (int j = 0; j < n; ++j) {
    out[j] = w0 * q0[j] + w1 * (m1[j] + p1[j]) + w2 * (m2[j] + p2[j]) +
             w3 * (m3[j] + p3[j]) + w4 * (m4[j] + p4[j]) +
             w5 * (m5[j] + p5[j]);
  }
}

// Row r of a row-blurred plane blurred down its columns.
template <typename T>
void BlurColumnAt(const SsimPass<T>& p, const T* plane, int r, T* out) {
  const T* q[2 * kR + 1];
  for (int k = -kR; k <= kR; ++k) {
    const int row = r + k;
    q[k + kR] = row >= 0 && row < p.rows
                    ? plane + static_cast<size_t>(row) * p.row_len
                    : p.zero_row;
  }
  BlurColumn(q[5], q[4], q[6], q[3], q[7], q[2], q[8], q[1], q[9], q[0], q[10],
             p.row_len, p.weights, out);
}

// Sum of n values with 16 partial sums (vectorizes without reassociating
// a single running sum).
template <typename T>
double RowSum(const T* v, int n) {
  T part[16] = {};
  int j = 0;
  for (; j + 16 <= n; j += 16)
    for (int l = 0; l < 16; ++l) part[l] += v[j + l];
  double sum = 0;
  for (int l = 0; l < 16; ++l) sum += part[l];
  for (; j < n; ++j) sum += v[j];
  return sum;
}

// Sum of |a - b| over n values, as RowSum.
template <typename T>
double RowAbsDiffSum(const T* a, const T* b, int n) {
  T part[16] = {};
  int j = 0;
  for (; j + 16 <= n; j += 16) {
    for (int l = 0; l < 16; ++l) {
      const T d = a[j + l] - b[j + l];
      part[l] += d < 0 ? -d : d;
    }
  }
  double sum = 0;
  for (int l = 0; l < 16; ++l) sum += part[l];
  for (; j < n; ++j) sum += a[j] > b[j] ? a[j] - b[j] : b[j] - a[j];
  return sum;
}

// Blurs K planes with the window. make(r, scratch, src) points src[k] at
// row r of plane k (row_len values with 5 C readable zeros on both sides),
// writing it into scratch[k] (such a padded row) if it is not stored so
// already. use(r, blurred) then gets row r of every blurred plane (in
// per-thread rows it may overwrite).
template <int K, typename T, typename Make, typename Use>
void BlurPlanes(const SsimPass<T>& p, Make make, Use use) {
  static_assert(K <= kMaxPlanes, "more planes than scratch rows");
  const size_t n = static_cast<size_t>(p.rows) * p.row_len;
  const int margin = kR * p.channels;
  const int padded_len = p.row_len + 2 * margin;
#pragma omp parallel if (p.parallel)
  {
    T* mine = p.thread_rows + p.thread_stride * omp_get_thread_num();
    T* scratch[K];
    T* blurred[K];
    for (int k = 0; k < K; ++k) {
      scratch[k] = mine + static_cast<size_t>(k) * padded_len + margin;
      blurred[k] = mine + static_cast<size_t>(kMaxPlanes) * padded_len +
                   static_cast<size_t>(k) * p.row_len;
    }
#pragma omp for schedule(static)
    for (int r = 0; r < p.rows; ++r) {
      const T* src[K];
      make(r, scratch, src);
      for (int k = 0; k < K; ++k) {
        BlurRow(src[k], p.row_len, p.channels, p.weights,
                p.planes + k * n + static_cast<size_t>(r) * p.row_len);
      }
    }
    // (the loop's barrier: every row is row-blurred before columns start)
#pragma omp for schedule(static)
    for (int r = 0; r < p.rows; ++r) {
      for (int k = 0; k < K; ++k)
        BlurColumnAt(p, p.planes + k * n, r, blurred[k]);
      use(r, blurred);
    }
  }
}

template <typename T>
void TargetStats(const SsimPass<T>& p, T* mu, T* var) {
  BlurPlanes<2>(
      p,
      [&](int r, T* const* scratch, const T** src) {
        const T* y = p.y + static_cast<size_t>(r) * p.row_len;
        T* __restrict a = scratch[0];
        T* __restrict b = scratch[1];
        for (int j = 0; j < p.row_len; ++j) {
          a[j] = y[j];
          b[j] = y[j] * y[j];
        }
        src[0] = a;
        src[1] = b;
      },
      [&](int r, T* const* blurred) {
        const size_t off = static_cast<size_t>(r) * p.row_len;
        const T* __restrict m = blurred[0];
        const T* __restrict e = blurred[1];
        T* __restrict mu_row = mu + off;
        T* __restrict var_row = var + off;
        for (int j = 0; j < p.row_len; ++j) {
          mu_row[j] = m[j];
          var_row[j] = e[j] - m[j] * m[j];
        }
      });
}

// SSIM of one row from the blurred x, x^2, x y (s overwrites e_xx); with
// kGrad also d S / d (G x, G x^2, G x y) / n into ga, gb, gc:
// d mean S / d x = G ga + 2 x G gb + y G gc (the window is its own
// adjoint under zero padding).
template <bool kGrad, typename T>
void SsimRow(int n, const T* __restrict mu_x, T* __restrict e_xx,
             const T* __restrict e_xy, const T* __restrict mu_y,
             const T* __restrict var_y, T inv_count, T* __restrict ga,
             T* __restrict gb, T* __restrict gc) {
  const T c1 = static_cast<T>(kSsimC1), c2 = static_cast<T>(kSsimC2);
  for (int j = 0; j < n; ++j) {
    const T mx = mu_x[j], my = mu_y[j];
    const T sxx = e_xx[j] - mx * mx;
    const T sxy = e_xy[j] - mx * my;
    const T a1 = 2 * mx * my + c1, a2 = 2 * sxy + c2;
    const T b1 = mx * mx + my * my + c1, b2 = sxx + var_y[j] + c2;
    const T inv = 1 / (b1 * b2);
    const T s = a1 * a2 * inv;
    e_xx[j] = s;
    if (kGrad) {
      const T ds_dsxx = -s * b1 * inv;  // -s / b2
      const T ds_dsxy = 2 * a1 * inv;
      const T ds_dmx = 2 * my * a2 * inv - 2 * mx * s * b2 * inv;
      ga[j] = (ds_dmx - 2 * mx * ds_dsxx - my * ds_dsxy) * inv_count;
      gb[j] = ds_dsxx * inv_count;
      gc[j] = ds_dsxy * inv_count;
    }
  }
}

template <typename T>
double Evaluate(const SsimPass<T>& p) {
  const bool want_grad = p.d_x != nullptr;
  const size_t n = static_cast<size_t>(p.rows) * p.row_len;
  const int margin = kR * p.channels;
  const size_t padded_len = p.row_len + 2 * margin;
  const size_t term_plane = padded_len * p.rows;
  const T inv_count = static_cast<T>(1.0 / static_cast<double>(n));
  BlurPlanes<3>(
      p,
      [&](int r, T* const* scratch, const T** src) {
        const size_t off = static_cast<size_t>(r) * p.row_len;
        const double* __restrict x = p.x + off;
        const T* __restrict y = p.y + off;
        T* __restrict a = scratch[0];
        T* __restrict b = scratch[1];
        T* __restrict c = scratch[2];
        for (int j = 0; j < p.row_len; ++j) {
          const T v = static_cast<T>(x[j]);
          a[j] = v;
          b[j] = v * v;
          c[j] = v * y[j];
        }
        if (p.l1) p.row_sums[p.rows + r] = RowAbsDiffSum(a, y, p.row_len);
        for (int k = 0; k < 3; ++k) src[k] = scratch[k];
      },
      [&](int r, T* const* blurred) {
        const size_t off = static_cast<size_t>(r) * p.row_len;
        T* s = blurred[1];
        if (want_grad) {
          T* ga = p.grad_terms + r * padded_len + margin;
          SsimRow<true>(p.row_len, blurred[0], s, blurred[2], p.mu_y + off,
                        p.var_y + off, inv_count, ga, ga + term_plane,
                        ga + 2 * term_plane);
        } else {
          SsimRow<false, T>(p.row_len, blurred[0], s, blurred[2],
                            p.mu_y + off, p.var_y + off, inv_count, nullptr,
                            nullptr, nullptr);
        }
        p.row_sums[r] = RowSum(s, p.row_len);
        if (p.map) {
          double* __restrict map = p.map + off;
          for (int j = 0; j < p.row_len; ++j) map[j] = s[j];
        }
      });
  if (want_grad) {
    BlurPlanes<3>(
        p,
        [&](int r, T* const*, const T** src) {
          const T* row = p.grad_terms + r * padded_len + margin;
          for (int k = 0; k < 3; ++k) src[k] = row + k * term_plane;
        },
        [&](int r, T* const* blurred) {
          const size_t off = static_cast<size_t>(r) * p.row_len;
          const double* __restrict x = p.x + off;
          const T* __restrict y = p.y + off;
          const T* __restrict ga = blurred[0];
          const T* __restrict gb = blurred[1];
          const T* __restrict gc = blurred[2];
          double* __restrict d = p.d_x + off;
          const double scale = p.grad_scale;
          const double l1_scale = p.l1 ? p.l1_grad_scale / n : 0.0;
          for (int j = 0; j < p.row_len; ++j) {
            const T v = static_cast<T>(x[j]);
            const T sign = T(v > y[j]) - T(v < y[j]);
            d[j] = scale * static_cast<double>(ga[j] + 2 * v * gb[j] +
                                               y[j] * gc[j]) +
                   l1_scale * static_cast<double>(sign);
          }
        });
  }
  double sum = 0, l1 = 0;
  for (int r = 0; r < p.rows; ++r) {
    sum += p.row_sums[r];
    l1 += p.row_sums[p.rows + r];
  }
  if (p.l1) *p.l1 = l1 / static_cast<double>(n);
  return sum / static_cast<double>(n);
}

template <typename T>
const SsimKernelSet<T> kKernels = {&TargetStats<T>, &Evaluate<T>};

}  // namespace

const SsimKernelSet<float>& FloatKernels() { return kKernels<float>; }
const SsimKernelSet<double>& DoubleKernels() { return kKernels<double>; }

}  // namespace ES_SSIM_ISA
}  // namespace es
