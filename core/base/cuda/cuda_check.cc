#include "core/base/cuda/cuda_check.h"

#include <cstdlib>
#include <cstring>
#include <string>

namespace es {
namespace cuda {

bool SyncAfterLaunch() {
  static const bool sync = [] {
    const char* v = std::getenv("ES_CUDA_SYNC");
    return v != nullptr && std::strcmp(v, "1") == 0;
  }();
  return sync;
}

void CheckLaunch(const char* kernel, const char* file, int line) {
  cudaError_t status = cudaGetLastError();
  if (status == cudaSuccess && SyncAfterLaunch()) {
    status = cudaDeviceSynchronize();
  }
  if (status != cudaSuccess) {
    ThrowCudaError(cudaGetErrorString(status),
                   (std::string("kernel ") + kernel).c_str(), file, line);
  }
}

}  // namespace cuda
}  // namespace es
