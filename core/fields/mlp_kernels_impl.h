// The matrix products of core/fields/mlp_kernels.h. Included only by
// mlp_kernels_{sse2,avx2,avx512}.cc, each compiled for its instruction set
// with ES_MLP_ISA naming its namespace. Everything here has internal
// linkage and calls no out-of-line library code, so no function compiled
// for AVX2 / AVX-512 can be merged into, or called from, code that runs on
// a CPU without it.
//
// Both products are written as sums of scaled rows (c_row += s * b_row) in
// register tiles of kTileRows rows by two vectors of columns (GCC vector
// extensions, as wide as the instruction set's registers): each loaded
// piece of b serves kTileRows accumulators. Columns past the last full
// tile go through one-vector and then one-column tiles, so any shape is
// exact. One source for doubles and floats (T).

#if !defined(ES_MLP_ISA)
#error "define ES_MLP_ISA before this header"
#endif

#include "core/base/simd_vector.h"
#include "core/fields/mlp_kernels.h"

namespace es {
namespace ES_MLP_ISA {
namespace {

constexpr int kTileRows = 4;

// c[r][j] (r < R, j < V lanes; rows ldc apart) = init + sum_p a_r[p] b[p][j],
// where a_r[p] = a[r * a_row + p * a_step] (so a is read as given or
// transposed) and b rows are ldb apart. init is c itself (accumulate), the
// bias, or zero.
template <typename T, int R, int V>
inline void VectorTile(int k, const T* __restrict a, int a_row, int a_step,
                       const T* __restrict b, int ldb, const T* __restrict bias,
                       bool accumulate, T* __restrict c, int ldc) {
  typedef typename SimdOf<T>::Vec VecT;
  constexpr int kLanesT = SimdOf<T>::kLanes;
  VecT acc[R][V];
  for (int r = 0; r < R; ++r) {
    for (int v = 0; v < V; ++v) {
      acc[r][v] = accumulate        ? Load(c + r * ldc + v * kLanesT)
                  : bias != nullptr ? Load(bias + v * kLanesT)
                                    : VecT{};
    }
  }
  for (int p = 0; p < k; ++p) {
    const T* bp = b + static_cast<long>(p) * ldb;
    VecT bv[V];
    for (int v = 0; v < V; ++v) bv[v] = Load(bp + v * kLanesT);
    for (int r = 0; r < R; ++r) {
      const T s = a[r * a_row + static_cast<long>(p) * a_step];
      for (int v = 0; v < V; ++v) acc[r][v] += s * bv[v];
    }
  }
  for (int r = 0; r < R; ++r) {
    for (int v = 0; v < V; ++v) Store(acc[r][v], c + r * ldc + v * kLanesT);
  }
}

// The same for a single column j = 0.
template <typename T, int R>
inline void ColumnTile(int k, const T* __restrict a, int a_row, int a_step,
                       const T* __restrict b, int ldb, const T* __restrict bias,
                       bool accumulate, T* __restrict c, int ldc) {
  T acc[R];
  for (int r = 0; r < R; ++r) {
    acc[r] = accumulate ? c[r * ldc] : bias != nullptr ? bias[0] : T(0);
  }
  for (int p = 0; p < k; ++p) {
    const T bp = b[static_cast<long>(p) * ldb];
    for (int r = 0; r < R; ++r)
      acc[r] += a[r * a_row + static_cast<long>(p) * a_step] * bp;
  }
  for (int r = 0; r < R; ++r) c[r * ldc] = acc[r];
}

// One band of R output rows over all n columns: two-vector tiles, then at
// most one one-vector tile, then single columns.
template <typename T, int R>
inline void Band(int k, int n, const T* a, int a_row, int a_step, const T* b,
                 const T* bias, bool accumulate, T* c) {
  constexpr int kLanesT = SimdOf<T>::kLanes;
  auto offset = [bias](int j) { return bias != nullptr ? bias + j : nullptr; };
  int j = 0;
  for (; j + 2 * kLanesT <= n; j += 2 * kLanesT) {
    VectorTile<T, R, 2>(k, a, a_row, a_step, b + j, n, offset(j), accumulate,
                        c + j, n);
  }
  for (; j + kLanesT <= n; j += kLanesT) {
    VectorTile<T, R, 1>(k, a, a_row, a_step, b + j, n, offset(j), accumulate,
                        c + j, n);
  }
  for (; j < n; ++j) {
    ColumnTile<T, R>(k, a, a_row, a_step, b + j, n, offset(j), accumulate,
                     c + j, n);
  }
}

// c (rows x n) = sum_p a_r[p] b[p] over k, kTileRows rows at a time.
template <typename T>
void Rows(int rows, int k, int n, const T* a, int a_row, int a_step, const T* b,
          const T* bias, bool accumulate, T* c) {
  int r = 0;
  for (; r + kTileRows <= rows; r += kTileRows) {
    Band<T, kTileRows>(k, n, a + static_cast<long>(r) * a_row, a_row, a_step, b,
                       bias, accumulate, c + static_cast<long>(r) * n);
  }
  for (; r < rows; ++r) {
    Band<T, 1>(k, n, a + static_cast<long>(r) * a_row, a_row, a_step, b, bias,
               accumulate, c + static_cast<long>(r) * n);
  }
}

template <typename T>
void Multiply(int rows, int k, int n, const T* a, const T* b, const T* bias,
              bool accumulate, T* c) {
  Rows(rows, k, n, a, /*a_row=*/k, /*a_step=*/1, b, bias, accumulate, c);
}

// c (m x n) += a^T b: output row i is the sum over the batch rows p of
// a[p][i] b[p], so a is read down its columns.
template <typename T>
void MultiplyTransposed(int rows, int m, int n, const T* a, const T* b, T* c) {
  Rows(m, rows, n, a, /*a_row=*/1, /*a_step=*/m, b,
       static_cast<const T*>(nullptr),
       /*accumulate=*/true, c);
}

}  // namespace
const MlpKernelSet& Kernels() {
  static const MlpKernelSet kernels{
      &Multiply<double>, &MultiplyTransposed<double>, &Multiply<float>,
      &MultiplyTransposed<float>};
  return kernels;
}

}  // namespace ES_MLP_ISA
}  // namespace es
