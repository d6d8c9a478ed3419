// The tile kernels for AVX2 + FMA (compile flags: CMakeLists.txt).
#define ES_TILE_ISA tile_avx2
#define ES_TILE_FULL_ROWS 1
#include "core/render/tile_kernels_impl.h"
