// The MLP's matrix products for SSE2, the baseline every x86-64 CPU runs
// (compile flags: CMakeLists.txt).
#define ES_MLP_ISA mlp_sse2
#include "core/fields/mlp_kernels_impl.h"
