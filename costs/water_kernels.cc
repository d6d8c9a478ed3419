#include "costs/water_kernels.h"

namespace es {

const WaterKernelSet& WaterKernels(SimdLevel level) {
  return ForSimdLevel(level, &water_kernels_sse2::Kernels,
                      &water_kernels_avx2::Kernels,
                      &water_kernels_avx512::Kernels)();
}

}  // namespace es
