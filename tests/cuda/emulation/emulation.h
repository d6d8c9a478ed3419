#ifndef EULERSPLAT_TESTS_CUDA_EMULATION_EMULATION_H_
#define EULERSPLAT_TESTS_CUDA_EMULATION_EMULATION_H_

// The CUDA kernel language on the host, for -DES_CUDA_EMULATION=ON: the
// backend's .cu files, their launches rewritten by launches.py, compile as
// C++ with this header forced in. A launch runs its blocks one after
// another and each block's threads as std::threads, so barriers, warp
// votes and shuffles, shared memory and atomics behave as the kernels
// expect; a missing barrier shows as a data race under ThreadSanitizer.
// It checks the kernels' logic without a GPU, slowly; it says nothing of
// their speed, and of the device only what the CUDA programming model
// promises.

#include <algorithm>
#include <atomic>
#include <barrier>
#include <bit>
#include <cmath>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <cuda_runtime_api.h>

#define __global__
#define __device__
#define __host__
#define __shared__ static  // one block runs at a time
#define __launch_bounds__(threads)

struct dim3 {
  unsigned x = 1, y = 1, z = 1;
  dim3(unsigned x_ = 1, unsigned y_ = 1, unsigned z_ = 1)
      : x(x_), y(y_), z(z_) {}
};
inline thread_local dim3 threadIdx, blockIdx;
inline dim3 blockDim, gridDim;
using std::max;
using std::min;

inline unsigned __float_as_uint(float f) { return std::bit_cast<unsigned>(f); }
inline long long __double_as_longlong(double d) {
  return std::bit_cast<long long>(d);
}

namespace es {
namespace emulation {

constexpr int kWarp = 32;
constexpr int kMaxWarps = 32;  // 1024 threads

// The running block's barriers and the scratch of its collective calls.
struct Block {
  std::unique_ptr<std::barrier<>> all;
  std::vector<std::unique_ptr<std::barrier<>>> warps;
  std::atomic<int> count{0};
  std::atomic<int> vote[kMaxWarps];
  float lanes[kMaxWarps][kWarp];
};
inline Block block;
inline std::mutex atomics;

inline int Thread() { return threadIdx.x + threadIdx.y * blockDim.x; }

template <typename Body>
void Launch(dim3 grid, dim3 threads, Body body) {
  gridDim = grid;
  blockDim = threads;
  const int n = threads.x * threads.y;
  for (unsigned by = 0; by < grid.y; ++by) {
    for (unsigned bx = 0; bx < grid.x; ++bx) {
      block.all = std::make_unique<std::barrier<>>(n);
      block.warps.clear();
      for (int w = 0; w < (n + kWarp - 1) / kWarp; ++w) {
        block.warps.push_back(
            std::make_unique<std::barrier<>>(std::min(kWarp, n - kWarp * w)));
        block.vote[w] = 0;
      }
      block.count = 0;
      std::vector<std::thread> pool;
      for (int t = 0; t < n; ++t) {
        pool.emplace_back([&, t] {
          blockIdx = dim3(bx, by);
          threadIdx = dim3(t % threads.x, t / threads.x);
          body();
        });
      }
      for (std::thread& t : pool) t.join();
    }
  }
}

}  // namespace emulation
}  // namespace es

inline void __syncthreads() { es::emulation::block.all->arrive_and_wait(); }

inline int __syncthreads_count(int predicate) {
  auto& b = es::emulation::block;
  b.all->arrive_and_wait();
  if (predicate) b.count.fetch_add(1);
  b.all->arrive_and_wait();
  const int count = b.count.load();
  b.all->arrive_and_wait();
  if (es::emulation::Thread() == 0) b.count = 0;  // before the next adds
  return count;
}

inline bool __any_sync(unsigned, bool predicate) {
  auto& b = es::emulation::block;
  const int w = es::emulation::Thread() / es::emulation::kWarp;
  b.warps[w]->arrive_and_wait();
  if (predicate) b.vote[w] = 1;
  b.warps[w]->arrive_and_wait();
  const bool any = b.vote[w] != 0;
  b.warps[w]->arrive_and_wait();
  if (es::emulation::Thread() % es::emulation::kWarp == 0) b.vote[w] = 0;
  return any;
}

inline float __shfl_down_sync(unsigned, float value, int offset) {
  auto& b = es::emulation::block;
  const int w = es::emulation::Thread() / es::emulation::kWarp;
  const int lane = es::emulation::Thread() % es::emulation::kWarp;
  b.lanes[w][lane] = value;
  b.warps[w]->arrive_and_wait();
  const float out =
      lane + offset < es::emulation::kWarp ? b.lanes[w][lane + offset] : value;
  b.warps[w]->arrive_and_wait();
  return out;
}

template <typename T>
T atomicAdd(T* address, T value) {
  std::lock_guard<std::mutex> lock(es::emulation::atomics);
  const T old = *address;
  *address = old + value;
  return old;
}

template <typename T>
T atomicMax(T* address, T value) {
  std::lock_guard<std::mutex> lock(es::emulation::atomics);
  const T old = *address;
  *address = std::max(old, value);
  return old;
}

#endif  // EULERSPLAT_TESTS_CUDA_EMULATION_EMULATION_H_
