#include "core/render/project_kernels.h"

namespace es {

const ProjectKernelSet& ProjectKernels(SimdLevel level) {
  return ForSimdLevel(level, &project_sse2::Kernels, &project_avx2::Kernels,
                      &project_avx512::Kernels)();
}

}  // namespace es
