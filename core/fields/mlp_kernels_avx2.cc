// The MLP's matrix products for AVX2 + FMA (compile flags: CMakeLists.txt).
#define ES_MLP_ISA mlp_avx2
#include "core/fields/mlp_kernels_impl.h"
