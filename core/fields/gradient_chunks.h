#ifndef EULERSPLAT_CORE_FIELDS_GRADIENT_CHUNKS_H_
#define EULERSPLAT_CORE_FIELDS_GRADIENT_CHUNKS_H_

// A triplane's parameter gradient is zero almost everywhere (a point
// touches four texels per plane). Its producers can flag the chunks of
// kGradientChunk values they write, one char per chunk, so that whoever
// consumes the gradient (a parallel reduction, solvers/optim/sparse_adam.h)
// visits only those instead of scanning the whole block.

#include <algorithm>
#include <cstddef>

namespace es {

constexpr int kGradientChunk = 64;

inline int NumGradientChunks(size_t values) {
  return static_cast<int>((values + kGradientChunk - 1) / kGradientChunk);
}

// Sets the flags of the chunks that values [begin, end) fall in.
inline void FlagGradientChunks(size_t begin, size_t end, char* flags) {
  if (end <= begin) return;
  const size_t last = (end - 1) / kGradientChunk;
  for (size_t c = begin / kGradientChunk; c <= last; ++c) flags[c] = 1;
}

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_GRADIENT_CHUNKS_H_
