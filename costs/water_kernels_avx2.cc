// The water losses' blurs for AVX2 (compile flags:
// CMakeLists.txt).
#define ES_WATER_KERNELS_ISA water_kernels_avx2
#include "costs/water_kernels_impl.h"
