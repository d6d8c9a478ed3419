#include "core/render/project_kernels.h"

namespace es {

const ProjectKernelSet& ProjectKernels(SimdLevel level) {
  switch (ResolveSimdLevel(level)) {
    case SimdLevel::kAvx512:
      return project_avx512::Kernels();
    case SimdLevel::kAvx2:
      return project_avx2::Kernels();
    default:
      return project_sse2::Kernels();
  }
}

}  // namespace es
