// SSIM's kernels for AVX2 + FMA (compile flags: CMakeLists.txt).
#define ES_SSIM_ISA ssim_avx2
#include "core/metrics/ssim_kernels_impl.h"
