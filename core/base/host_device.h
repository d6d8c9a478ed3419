#ifndef EULERSPLAT_CORE_BASE_HOST_DEVICE_H_
#define EULERSPLAT_CORE_BASE_HOST_DEVICE_H_

// Markers for maths that both the CPU code and the CUDA kernels compile
// (the per-Gaussian and per-pixel formulas), so each is written once. Under
// nvcc a function is built for host and device; elsewhere (the CPU build,
// the CUDA emulation) the markers are plain C++. ES_FORCE_INLINE keeps such
// a function inside the CPU's `omp simd` lane loops, which vectorize only
// when nothing in them is a call.
#if defined(__CUDACC__)
#define ES_HOST_DEVICE __host__ __device__
#define ES_FORCE_INLINE __forceinline__
#else
#define ES_HOST_DEVICE
#define ES_FORCE_INLINE inline __attribute__((always_inline))
#endif

#endif  // EULERSPLAT_CORE_BASE_HOST_DEVICE_H_
