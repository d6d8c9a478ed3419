// The water losses' blurs for AVX-512 (compile flags:
// CMakeLists.txt).
#define ES_WATER_FILTER_ISA water_filter_avx512
#include "costs/water_filter_kernels_impl.h"
