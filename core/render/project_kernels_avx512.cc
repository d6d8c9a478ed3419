// The projection kernels for AVX-512 (compile flags: CMakeLists.txt).
#define ES_PROJECT_ISA project_avx512
#include "core/render/project_kernels_impl.h"
