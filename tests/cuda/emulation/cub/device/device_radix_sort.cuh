#ifndef EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_RADIX_SORT_CUH_
#define EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_RADIX_SORT_CUH_

// cub::DeviceRadixSort::SortPairs as the backend calls it, on the host
// (emulation.h): stable, ascending, on key bits [begin_bit, end_bit) only.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include <cuda_runtime_api.h>

namespace cub {

struct DeviceRadixSort {
  template <typename Key, typename Value>
  static cudaError_t SortPairs(void* storage, size_t& bytes,
                               const Key* keys_in, Key* keys_out,
                               const Value* values_in, Value* values_out,
                               int count, int begin_bit, int end_bit) {
    if (storage == nullptr) {
      bytes = 16;
      return cudaSuccess;
    }
    const int bits = static_cast<int>(8 * sizeof(Key));
    const Key high = end_bit >= bits ? ~Key{0} : (Key{1} << end_bit) - 1;
    const Key mask = high & ~((Key{1} << begin_bit) - 1);
    std::vector<int> order(count);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return (keys_in[a] & mask) < (keys_in[b] & mask);
    });
    for (int i = 0; i < count; ++i) {
      keys_out[i] = keys_in[order[i]];
      values_out[i] = values_in[order[i]];
    }
    return cudaSuccess;
  }
};

}  // namespace cub

#endif  // EULERSPLAT_TESTS_CUDA_EMULATION_CUB_DEVICE_DEVICE_RADIX_SORT_CUH_
