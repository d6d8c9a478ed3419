// The water losses' blurs for SSE2, the baseline every x86-64 CPU runs
// (compile flags: CMakeLists.txt).
#define ES_WATER_KERNELS_ISA water_kernels_sse2
#include "costs/water_kernels_impl.h"
