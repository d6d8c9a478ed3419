#ifndef EULERSPLAT_CORE_FIELDS_MLP_KERNELS_H_
#define EULERSPLAT_CORE_FIELDS_MLP_KERNELS_H_

// The two matrix products of an MLP layer, compiled once per instruction
// set (mlp_kernels_{sse2,avx2,avx512}.cc from the one source in
// mlp_kernels_impl.h) and picked at run time (core/base/simd_level.h).
// Matrices are dense and row-major; core/fields/mlp.h is the caller.

#include "core/base/simd_level.h"

namespace es {

struct MlpKernelSet {
  // c (rows x n) = a (rows x k) b (k x n) + bias (n, nullable), or
  // c += a b when accumulate (bias then ignored).
  void (*multiply)(int rows, int k, int n, const double* a, const double* b,
                   const double* bias, bool accumulate, double* c);
  // c (m x n) += a^T b for a (rows x m) and b (rows x n).
  void (*multiply_transposed)(int rows, int m, int n, const double* a,
                              const double* b, double* c);
  // The same two in float (Mlp's float precision).
  void (*multiply_float)(int rows, int k, int n, const float* a,
                         const float* b, const float* bias, bool accumulate,
                         float* c);
  void (*multiply_transposed_float)(int rows, int m, int n, const float* a,
                                    const float* b, float* c);
};

const MlpKernelSet& MlpKernels(SimdLevel level);

#define ES_DECLARE_MLP_KERNELS(isa) \
  namespace isa {                   \
  const MlpKernelSet& Kernels();    \
  }
ES_DECLARE_MLP_KERNELS(mlp_sse2)
ES_DECLARE_MLP_KERNELS(mlp_avx2)
ES_DECLARE_MLP_KERNELS(mlp_avx512)
#undef ES_DECLARE_MLP_KERNELS

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_MLP_KERNELS_H_
