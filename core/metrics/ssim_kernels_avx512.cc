// SSIM's kernels for AVX-512 (compile flags: CMakeLists.txt).
#define ES_SSIM_ISA ssim_avx512
#include "core/metrics/ssim_kernels_impl.h"
