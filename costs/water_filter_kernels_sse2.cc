// The water losses' blurs for SSE2, the baseline every x86-64 CPU runs
// (compile flags: CMakeLists.txt).
#define ES_WATER_FILTER_ISA water_filter_sse2
#include "costs/water_filter_kernels_impl.h"
