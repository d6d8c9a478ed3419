// The projection kernels for SSE2, the baseline every x86-64 CPU runs
// (compile flags: CMakeLists.txt).
#define ES_PROJECT_ISA project_sse2
#include "core/render/project_kernels_impl.h"
