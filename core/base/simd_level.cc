#include "core/base/simd_level.h"

#include <glog/logging.h>

namespace es {

const char* SimdLevelName(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAuto:
      return "auto";
    case SimdLevel::kSse2:
      return "sse2";
    case SimdLevel::kAvx2:
      return "avx2";
    case SimdLevel::kAvx512:
      return "avx512";
  }
  return "?";
}

bool SimdLevelSupported(SimdLevel level) {
#if defined(ES_SIMD_X86)
  switch (level) {
    case SimdLevel::kAuto:
    case SimdLevel::kSse2:
      return true;
    case SimdLevel::kAvx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SimdLevel::kAvx512:
      return __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512dq");
  }
  return false;
#else
  // Elsewhere all three sets are the same portable build.
  return true;
#endif
}

SimdLevel BestSimdLevel() {
  static const SimdLevel best = [] {
    for (SimdLevel l : {SimdLevel::kAvx512, SimdLevel::kAvx2})
      if (SimdLevelSupported(l)) return l;
    return SimdLevel::kSse2;
  }();
  return best;
}

SimdLevel ResolveSimdLevel(SimdLevel level) {
  if (level == SimdLevel::kAuto) return BestSimdLevel();
  CHECK(SimdLevelSupported(level))
      << "this CPU lacks the " << SimdLevelName(level) << " instructions";
  return level;
}

}  // namespace es
