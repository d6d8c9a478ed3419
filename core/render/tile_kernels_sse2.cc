// The tile kernels for SSE2, the baseline every x86-64 CPU runs (compile flags:
// CMakeLists.txt).
#define ES_TILE_ISA tile_sse2
#define ES_TILE_FULL_ROWS 0
#include "core/render/tile_kernels_impl.h"
