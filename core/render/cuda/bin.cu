// Binning on the device: every kept Gaussian is listed once per tile it is
// binned to, and the list is radix sorted by (tile, depth), so each tile's
// Gaussians come out front to back, as rasterizer.cc's Project and Bin
// order them.

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include "core/base/cuda/cuda_check.h"
#include "core/base/cuda/kernel_grid.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

// Key of one entry: the tile in the high 32 bits, the depth's float bits in
// the low 32. Depths are past the near plane (> 0), and the bits of
// positive floats order as their values.
__device__ inline uint64_t EntryKey(int tile, float depth) {
  return (static_cast<uint64_t>(tile) << 32) | __float_as_uint(depth);
}

// Writes Gaussian n's entries from offsets[n] on, in index order (the sort
// is stable, so equal keys keep it).
__global__ void EmitEntriesKernel(int count, int tiles_x,
                                  const ProjectedGaussian* projected,
                                  const int* tiles, const int* offsets,
                                  uint64_t* keys, int* values) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count || tiles[n] == 0) return;
  const ProjectedGaussian& p = projected[n];
  int e = offsets[n];
  for (int ty = p.tile_y0; ty < p.tile_y1; ++ty) {
    for (int tx = p.tile_x0; tx < p.tile_x1; ++tx, ++e) {
      keys[e] = EntryKey(ty * tiles_x + tx, p.depth);
      values[e] = n;
    }
  }
}

// ranges[2t], ranges[2t + 1]: the first and one past the last entry of
// tile t among the sorted keys (left 0, 0 where a tile has none).
__global__ void TileRangesKernel(int entries, const uint64_t* keys,
                                 int* ranges) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= entries) return;
  const int tile = static_cast<int>(keys[e] >> 32);
  if (e == 0 || static_cast<int>(keys[e - 1] >> 32) != tile) {
    ranges[2 * tile] = e;
  }
  if (e == entries - 1 || static_cast<int>(keys[e + 1] >> 32) != tile) {
    ranges[2 * tile + 1] = e + 1;
  }
}

// Bits a tile index below num_tiles needs.
int TileBits(int num_tiles) {
  int bits = 0;
  while (bits < 31 && (1 << bits) < num_tiles) ++bits;
  return bits;
}

}  // namespace

int BinGaussians(int count, int tiles_x, int tiles_y,
                 const ProjectedGaussian* projected, const int* tiles,
                 BinScratch* scratch, DeviceBuffer<int>* gaussians,
                 int* ranges) {
  const int num_tiles = tiles_x * tiles_y;
  ES_CUDA_CHECK(cudaMemset(ranges, 0, 2 * sizeof(int) * num_tiles));
  if (count == 0) return 0;
  // Each Gaussian's first entry: the exclusive sum of the tile counts.
  scratch->offsets.Resize(count);
  size_t bytes = 0;
  ES_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, tiles,
                                              scratch->offsets.data(), count));
  scratch->cub.Resize(bytes > 0 ? bytes : 1);  // null storage: a size query
  ES_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scratch->cub.data(), bytes,
                                              tiles, scratch->offsets.data(),
                                              count));
  int last_offset = 0, last_tiles = 0;
  CopyToHost(&last_offset, scratch->offsets.data() + count - 1, sizeof(int));
  CopyToHost(&last_tiles, tiles + count - 1, sizeof(int));
  const int entries = last_offset + last_tiles;
  gaussians->Resize(entries);
  if (entries == 0) return 0;

  scratch->keys.Resize(entries);
  scratch->sorted_keys.Resize(entries);
  scratch->values.Resize(entries);
  EmitEntriesKernel<<<GridBlocks(count, kThreads), kThreads>>>(
      count, tiles_x, projected, tiles, scratch->offsets.data(),
      scratch->keys.data(), scratch->values.data());
  ES_CUDA_CHECK_LAUNCH("EmitEntriesKernel");

  const int end_bit = 32 + TileBits(num_tiles);
  bytes = 0;
  ES_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(
      nullptr, bytes, scratch->keys.data(), scratch->sorted_keys.data(),
      scratch->values.data(), gaussians->data(), entries, 0, end_bit));
  scratch->cub.Resize(bytes > 0 ? bytes : 1);
  ES_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(
      scratch->cub.data(), bytes, scratch->keys.data(),
      scratch->sorted_keys.data(), scratch->values.data(), gaussians->data(),
      entries, 0, end_bit));

  TileRangesKernel<<<GridBlocks(entries, kThreads), kThreads>>>(
      entries, scratch->sorted_keys.data(), ranges);
  ES_CUDA_CHECK_LAUNCH("TileRangesKernel");
  return entries;
}

}  // namespace cuda
}  // namespace es
