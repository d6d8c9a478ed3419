#include "core/fields/mlp_kernels.h"

namespace es {

const MlpKernelSet& MlpKernels(SimdLevel level) {
  return ForSimdLevel(level, &mlp_sse2::Kernels, &mlp_avx2::Kernels,
                      &mlp_avx512::Kernels)();
}

}  // namespace es
