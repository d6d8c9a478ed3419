#ifndef EULERSPLAT_CORE_BASE_CUDA_CUDA_CHECK_H_
#define EULERSPLAT_CORE_BASE_CUDA_CUDA_CHECK_H_

// ES_CUDA_CHECK(call) throws CudaError when a CUDA runtime call fails;
// ES_CUDA_CHECK_LAUNCH(name) after a kernel launch. Kernels run
// asynchronously, so a fault inside one is reported by the next call that
// waits for the device; with ES_CUDA_SYNC=1 in the environment every launch
// is waited for, and the error names the kernel that failed.

#include <cuda_runtime_api.h>

#include "core/base/cuda/cuda_error.h"

namespace es {
namespace cuda {

bool SyncAfterLaunch();  // ES_CUDA_SYNC=1, read once
void CheckLaunch(const char* kernel, const char* file, int line);

}  // namespace cuda
}  // namespace es

#define ES_CUDA_CHECK(call)                                              \
  do {                                                                   \
    const cudaError_t es_cuda_status = (call);                           \
    if (es_cuda_status != cudaSuccess) {                                 \
      cudaGetLastError(); /* clear it, unless the context is lost */     \
      ::es::cuda::ThrowCudaError(cudaGetErrorString(es_cuda_status),     \
                                 #call, __FILE__, __LINE__);             \
    }                                                                    \
  } while (0)

#define ES_CUDA_CHECK_LAUNCH(kernel) \
  ::es::cuda::CheckLaunch(kernel, __FILE__, __LINE__)

#endif  // EULERSPLAT_CORE_BASE_CUDA_CUDA_CHECK_H_
