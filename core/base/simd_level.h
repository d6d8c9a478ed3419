#ifndef EULERSPLAT_CORE_BASE_SIMD_LEVEL_H_
#define EULERSPLAT_CORE_BASE_SIMD_LEVEL_H_

// The instruction sets our hot kernels are compiled for (the rasterizer's
// tile passes and projection, SSIM's blurs): each kernel file is built once
// per set and the best one the CPU supports is picked at run time, so a
// default (SSE2) build still runs AVX2 / AVX-512 code where it can.

namespace es {

// kAuto picks the best supported set.
enum class SimdLevel { kAuto = 0, kSse2, kAvx2, kAvx512 };

const char* SimdLevelName(SimdLevel level);
bool SimdLevelSupported(SimdLevel level);
// The best level this CPU supports (never kAuto).
SimdLevel BestSimdLevel();
// `level` itself if supported, the best supported one for kAuto, and an
// error (glog CHECK) for a level the CPU lacks.
SimdLevel ResolveSimdLevel(SimdLevel level);

// Of one thing built per level (a kernel set's getter), the one for
// `level` resolved as above: every SIMD kernel family picks its build here.
template <typename T>
T ForSimdLevel(SimdLevel level, T sse2, T avx2, T avx512) {
  switch (ResolveSimdLevel(level)) {
    case SimdLevel::kAvx512:
      return avx512;
    case SimdLevel::kAvx2:
      return avx2;
    default:
      return sse2;
  }
}

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_SIMD_LEVEL_H_
