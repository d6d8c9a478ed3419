#include "core/fields/mlp_kernels.h"

namespace es {

const MlpKernelSet& MlpKernels(SimdLevel level) {
  switch (ResolveSimdLevel(level)) {
    case SimdLevel::kAvx512:
      return mlp_avx512::Kernels();
    case SimdLevel::kAvx2:
      return mlp_avx2::Kernels();
    default:
      return mlp_sse2::Kernels();
  }
}

}  // namespace es
