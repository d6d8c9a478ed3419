#include "core/render/tile_kernels.h"

#include <glog/logging.h>

namespace es {

int TileScratchSize(int num_features) {
  constexpr int kTilePixels = kTileSize * kTileSize;
  // Per pixel: T, suffix, the feature gradients; per lane: the extra
  // channels' gradients.
  return kTilePixels * (num_features + 2) + kTileSize * (num_features - 4);
}

template <>
const TileKernelSet<float>& TileKernels<float>(SimdLevel level,
                                               int num_extra) {
  return ForSimdLevel(level, &tile_sse2::FloatKernels,
                      &tile_avx2::FloatKernels,
                      &tile_avx512::FloatKernels)(num_extra);
}

template <>
const TileKernelSet<double>& TileKernels<double>(SimdLevel level,
                                                 int num_extra) {
  return ForSimdLevel(level, &tile_sse2::DoubleKernels,
                      &tile_avx2::DoubleKernels,
                      &tile_avx512::DoubleKernels)(num_extra);
}

}  // namespace es
