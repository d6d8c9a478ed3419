#ifndef EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_SCAN_CUH_
#define EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_SCAN_CUH_

// cub::DeviceScan::ExclusiveSum as the backend calls it, on the host
// (emulation.h): a size query with null storage, then the scan.

#include <cstddef>

#include <cuda_runtime_api.h>

namespace cub {

struct DeviceScan {
  template <typename T>
  static cudaError_t ExclusiveSum(void* storage, size_t& bytes, const T* in,
                                  T* out, int count) {
    if (storage == nullptr) {
      bytes = 16;
      return cudaSuccess;
    }
    T sum = 0;
    for (int i = 0; i < count; ++i) {
      const T v = in[i];
      out[i] = sum;
      sum += v;
    }
    return cudaSuccess;
  }
};

}  // namespace cub

#endif  // EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_SCAN_CUH_
