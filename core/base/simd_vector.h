#ifndef EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_
#define EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_

// For the kernel files built once per instruction set
// (*_kernels_{sse2,avx2,avx512}.cc): the widest vector of doubles or
// floats the including file's set has (GCC's vector extension), and
// unaligned loads and stores of it. It depends on the flags of the file
// that includes it, so everything here has internal linkage.

namespace es {
namespace {

#if defined(__AVX512F__)
constexpr int kVectorBytes = 64;
#elif defined(__AVX2__)
constexpr int kVectorBytes = 32;
#else
constexpr int kVectorBytes = 16;
#endif

// The vector of T (double or float) and its lane count.
template <typename T>
struct SimdOf {
  typedef T Vec __attribute__((vector_size(kVectorBytes)));
  static constexpr int kLanes = kVectorBytes / sizeof(T);
};

template <typename T>
inline typename SimdOf<T>::Vec Load(const T* p) {
  typename SimdOf<T>::Vec v;
  __builtin_memcpy(&v, p, sizeof(v));
  return v;
}

template <typename T>
inline void Store(const typename SimdOf<T>::Vec& v, T* p) {
  __builtin_memcpy(p, &v, sizeof(v));
}

// The double vector, which most kernels use.
typedef SimdOf<double>::Vec Vec;
constexpr int kLanes = SimdOf<double>::kLanes;

}  // namespace
}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_SIMD_VECTOR_H_
