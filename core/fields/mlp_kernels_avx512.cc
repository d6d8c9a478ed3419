// The MLP's matrix products for AVX-512 (compile flags: CMakeLists.txt).
#define ES_MLP_ISA mlp_avx512
#include "core/fields/mlp_kernels_impl.h"
