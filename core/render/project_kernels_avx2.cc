// The projection kernels for AVX2 + FMA (compile flags: CMakeLists.txt).
#define ES_PROJECT_ISA project_avx2
#include "core/render/project_kernels_impl.h"
