#include "core/base/cuda/device_buffer.h"

#include "core/base/cuda/cuda_check.h"

namespace es {
namespace cuda {

void* DeviceAllocate(size_t bytes) {
  if (bytes == 0) return nullptr;
  void* p = nullptr;
  ES_CUDA_CHECK(cudaMalloc(&p, bytes));
  return p;
}

void DeviceFree(void* p) {
  // Never throws (destructors call it); a failure here means an earlier
  // fault, which the next checked call reports.
  if (p != nullptr) cudaFree(p);
}

void CopyToDevice(void* device, const void* host, size_t bytes) {
  if (bytes == 0) return;
  ES_CUDA_CHECK(cudaMemcpy(device, host, bytes, cudaMemcpyHostToDevice));
}

void CopyToHost(void* host, const void* device, size_t bytes) {
  if (bytes == 0) return;
  ES_CUDA_CHECK(cudaMemcpy(host, device, bytes, cudaMemcpyDeviceToHost));
}

void DeviceZero(void* device, size_t bytes) {
  if (bytes == 0) return;
  ES_CUDA_CHECK(cudaMemset(device, 0, bytes));
}

}  // namespace cuda
}  // namespace es
