#include "core/base/cuda/cuda_error.h"

#include <cstdio>

#include <cuda_runtime_api.h>

namespace es {
namespace cuda {

void ThrowCudaError(const char* error_text, const char* call,
                    const char* file, int line) {
  throw CudaError(std::string("CUDA error in ") + file + ":" +
                  std::to_string(line) + ": " + call + ": " + error_text);
}

bool CudaDeviceAvailable(std::string* why) {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  std::string reason;
  if (status == cudaErrorNoDevice || (status == cudaSuccess && count == 0)) {
    reason = "no CUDA device is present";
  } else if (status == cudaErrorInsufficientDriver) {
    reason = "the NVIDIA driver is missing or older than this CUDA runtime (" +
             std::to_string(CUDART_VERSION / 1000) + "." +
             std::to_string(CUDART_VERSION % 1000 / 10) + ") needs";
  } else if (status != cudaSuccess) {
    reason = std::string("CUDA cannot be initialised: ") +
             cudaGetErrorString(status);
  }
  if (!reason.empty()) {
    cudaGetLastError();  // clear it: the next call starts clean
    if (why != nullptr) *why = reason;
    return false;
  }
  if (why != nullptr) *why = CudaDeviceDescription();
  return true;
}

std::string CudaDeviceDescription() {
  int device = 0;
  cudaDeviceProp prop;
  cudaError_t status = cudaGetDevice(&device);
  if (status == cudaSuccess) {
    status = cudaGetDeviceProperties(&prop, device);
  }
  if (status != cudaSuccess) {
    cudaGetLastError();
    ThrowCudaError(cudaGetErrorString(status), "cudaGetDeviceProperties",
                   __FILE__, __LINE__);
  }
  char text[320];
  std::snprintf(text, sizeof(text), "%s (sm_%d%d, %d SMs, %.1f GiB)",
                prop.name, prop.major, prop.minor, prop.multiProcessorCount,
                static_cast<double>(prop.totalGlobalMem) / (1 << 30));
  return text;
}

}  // namespace cuda
}  // namespace es
