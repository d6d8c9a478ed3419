#ifndef EULERSPLAT_CORE_RENDER_TILE_KERNELS_H_
#define EULERSPLAT_CORE_RENDER_TILE_KERNELS_H_

// The rasterizer's per-tile forward and backward passes, compiled once per
// instruction set (tile_kernels_{sse2,avx2,avx512}.cc from the one source in
// tile_kernels_impl.h) and picked at run time from what the CPU supports,
// so a default (SSE2) build still runs AVX2 / AVX-512 code where it can.

#include <cmath>

#include "core/render/raster_constants.h"
#include "core/base/simd_level.h"

namespace es {

// What the tile passes read and write, in the precision S of the inner
// loops. Per binned Gaussian k (depth order), one record of record_stride
// values at splat[record_stride k..] (TileRecordStride; a float record is
// one 64-byte cache line when the features fit): its pixel box px0, px1,
// py0, py1 (small integers, exact in S), mean x, mean y, conic a, b, c,
// opacity, the sigma cutoff (TileSigmaCutoff), then the features r, g, b,
// depth, extras: one cache miss per entry, where three arrays cost three.
// Per tile: tile_entries [tile_offsets[t], tile_offsets[t + 1]) its
// Gaussians, front to back.
template <typename S>
struct TilePass {
  int width = 0, height = 0, tiles_x = 0;
  int num_features = 4;  // r, g, b, depth, then num_extra extras
  int num_extra = 0;
  const int* tile_offsets = nullptr;
  const int* tile_entries = nullptr;
  const S* splat = nullptr;
  int record_stride = 0;
  double background[3] = {0, 0, 0};

  // Forward outputs (per pixel), and the state Backward reads back.
  double* rgb = nullptr;    // 3 per pixel
  double* alpha = nullptr;
  double* depth = nullptr;
  double* extra = nullptr;  // num_extra per pixel
  S* t_final = nullptr;     // transmittance after the last Gaussian
  int* last = nullptr;      // entries of the pixel's list used + 1

  // Backward inputs (nullptr: zero) and outputs. Per tile t,
  // tile_last_entry[t] is the depth index k of the last Gaussian in its
  // list any of its pixels used (-1: none); the entries behind it took no
  // part and are not written (two thirds of all entries at 1168x880 with
  // 300k Gaussians: writing their zeros was a cache miss each). Per entry
  // e of tile_entries (one Gaussian in one tile) up to that one, at slot
  // entry_slot[e] of entry_grad, grad_stride values d mean2d (2), d conic
  // (3), d opacity, then one per feature: the tile's share of the
  // Gaussian's gradient. Each tile writes only its own entries' slots, so
  // the tiles need no atomics and the per-Gaussian sums (taken afterwards,
  // over the slots of tiles whose tile_last_entry is not in front of the
  // Gaussian) do not depend on the thread count.
  const double* d_rgb = nullptr;
  const double* d_alpha = nullptr;
  const double* d_depth = nullptr;
  const double* d_extra = nullptr;
  const int* entry_slot = nullptr;
  S* entry_grad = nullptr;
  int* tile_last_entry = nullptr;
  int grad_stride = 0;
};

// Offsets in a record (TilePass::splat).
constexpr int kTileRecordBox = 0;
constexpr int kTileRecordGeom = 4;
constexpr int kTileRecordCutoff = 10;
constexpr int kTileRecordFeature = 11;
constexpr int kTileGradHead = 6;

// Where sigma = 0.5 d^T conic d exceeds this, alpha = opacity exp(-sigma)
// is below kMinAlpha by a margin (0.1 in sigma, far above the rounding of
// sigma in float): the tile passes skip a row whose least sigma over its
// pixels is above it (a row of the pixel box the ellipse misses, as a
// needle's box has many). Such pixels take no part in either pass, so the
// skip changes no value. In the precision of the pass: a float log is all
// a 0.1 margin needs, and cheaper.
template <typename S>
inline S TileSigmaCutoff(S opacity) {
  return std::log(opacity) + static_cast<S>(-std::log(kMinAlpha) + 0.1);
}

// A record's length in values of S for num_features features: rounded up
// to whole 64-byte lines (records start on a line when splat does).
template <typename S>
constexpr int TileRecordStride(int num_features) {
  constexpr int kLine = 64 / static_cast<int>(sizeof(S));
  return (kTileRecordFeature + num_features + kLine - 1) / kLine * kLine;
}

// Scalars of per-thread scratch a tile pass needs.
int TileScratchSize(int num_features);

template <typename S>
struct TileKernelSet {
  // Renders one tile into the forward outputs; returns the Gaussian-pixel
  // pairs it evaluated.
  long long (*forward)(const TilePass<S>& pass, int tile, S* scratch);
  // Writes the tile's share of every Gaussian's 2D gradient (entry_grad).
  void (*backward)(const TilePass<S>& pass, int tile, S* scratch);
};

// The kernels for an instruction set and a number of extra channels.
template <typename S>
const TileKernelSet<S>& TileKernels(SimdLevel level, int num_extra);

// One set per instruction set (internal to the dispatch).
#define ES_DECLARE_TILE_KERNELS(isa)                 \
  namespace isa {                                    \
  const TileKernelSet<float>& FloatKernels(int);     \
  const TileKernelSet<double>& DoubleKernels(int);   \
  }
ES_DECLARE_TILE_KERNELS(tile_sse2)
ES_DECLARE_TILE_KERNELS(tile_avx2)
ES_DECLARE_TILE_KERNELS(tile_avx512)
#undef ES_DECLARE_TILE_KERNELS

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_TILE_KERNELS_H_
