// The tile kernels for AVX-512 F/VL/BW/DQ (compile flags: CMakeLists.txt).
#define ES_TILE_ISA tile_avx512
#define ES_TILE_FULL_ROWS 1
#include "core/render/tile_kernels_impl.h"
