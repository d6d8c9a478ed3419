// SSIM's kernels for SSE2, the baseline every x86-64 CPU runs (compile flags:
// CMakeLists.txt).
#define ES_SSIM_ISA ssim_sse2
#include "core/metrics/ssim_kernels_impl.h"
