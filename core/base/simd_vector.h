#ifndef EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_
#define EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_

// For the kernel files built once per instruction set
// (*_kernels_{sse2,avx2,avx512}.cc): the widest vector of doubles the
// including file's set has (GCC's vector extension), and unaligned loads
// and stores of it. It depends on the flags of the file that includes it,
// so everything here has internal linkage.

namespace es {
namespace {

#if defined(__AVX512F__)
constexpr int kVectorBytes = 64;
#elif defined(__AVX2__)
constexpr int kVectorBytes = 32;
#else
constexpr int kVectorBytes = 16;
#endif
typedef double Vec __attribute__((vector_size(kVectorBytes)));
constexpr int kLanes = kVectorBytes / sizeof(double);

inline Vec Load(const double* p) {
  Vec v;
  __builtin_memcpy(&v, p, sizeof(v));
  return v;
}

inline void Store(const Vec& v, double* p) {
  __builtin_memcpy(p, &v, sizeof(v));
}

}  // namespace
}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_
