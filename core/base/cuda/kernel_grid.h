#ifndef EULERSPLAT_CORE_BASE_CUDA_KERNEL_GRID_H_
#define EULERSPLAT_CORE_BASE_CUDA_KERNEL_GRID_H_

// What the element-wise and reducing kernels share: the 1-D grid over n
// items, a thread's item in it, and a block's sum. Device code: include it
// from .cu files only.

namespace es {
namespace cuda {

// Blocks of `threads` threads that cover n items.
inline int GridBlocks(long long n, int threads) {
  return static_cast<int>((n + threads - 1) / threads);
}

// This thread's item in a 1-D grid.
__device__ inline long long GridIndex() {
  return static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
}

// Block b's sum of v into partials[b]: a tree over shared memory, so a sum
// does not depend on the order threads run in. Every thread of a block of
// kThreads threads calls it.
template <int kThreads>
__device__ void BlockSum(double v, double* partials) {
  __shared__ double s[kThreads];
  const int t = threadIdx.x;
  s[t] = v;
  __syncthreads();
  for (int half = kThreads / 2; half > 0; half /= 2) {
    if (t < half) s[t] += s[t + half];
    __syncthreads();
  }
  if (t == 0) partials[blockIdx.x] = s[0];
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_CUDA_KERNEL_GRID_H_
