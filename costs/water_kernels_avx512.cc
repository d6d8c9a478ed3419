// The water losses' blurs for AVX-512 (compile flags:
// CMakeLists.txt).
#define ES_WATER_KERNELS_ISA water_kernels_avx512
#include "costs/water_kernels_impl.h"
