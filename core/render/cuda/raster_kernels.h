#ifndef EULERSPLAT_CORE_RENDER_CUDA_RASTER_KERNELS_H_
#define EULERSPLAT_CORE_RENDER_CUDA_RASTER_KERNELS_H_

// The device rasterizer's kernels, as DeviceRasterizer (device_rasterizer.cc)
// launches them: plain types only, so host code compiled without nvcc can
// call them. Each mirrors a CPU twin of core/render, whose conventions it
// keeps: project.cu the float projection of project_kernels_impl.h, bin.cu
// the depth sort and binning of rasterizer.cc, tiles.cu the tile passes of
// tile_kernels_impl.h. All pointers are device pointers; launches go to the
// default stream.

#include <cstdint>

#include "core/base/cuda/device_buffer.h"
#include "core/render/project_kernels.h"
#include "core/render/raster_constants.h"
#include "core/render/tile_kernels.h"

namespace es {
namespace cuda {

// Extra channels (e.g. the dynamic probability) the device passes support:
// their per-pixel sums live in registers.
constexpr int kMaxDeviceExtra = 4;
constexpr int kMaxDeviceFeatures = 4 + kMaxDeviceExtra;

// One Gaussian after projection: what the tile passes read (the CPU's
// ProjectedSplat, in float as the CPU's float tile records hold it).
struct ProjectedGaussian {
  float mean[2];   // pixel coordinates
  float conic[3];  // a, b, c: sigma = 0.5 (a dx^2 + c dy^2) + b dx dy
  float opacity;
  float depth;     // camera z
  int radius;      // ceil(3 sqrt(largest eigenvalue)), px; 0 if culled
  int px0, px1, py0, py1;  // pixels that can reach kMinAlpha, plus a margin
  int tile_x0, tile_x1, tile_y0, tile_y1;  // tiles it is binned to
};

// Projects Gaussians [0, count) of `in` (device splat pointers): per
// Gaussian its projection, its features (r, g, b, depth, then the
// num_extra values of `extra`, [n][e]) at features[n * (4 + num_extra)],
// and tiles[n], the number of tiles it is binned to (0: culled, as
// ProjectSplat decides). *visible (zeroed here) counts the survivors.
void ProjectForward(const ProjectionInput& in, int count, int num_extra,
                    const double* extra, ProjectedGaussian* projected,
                    float* features, int* tiles, int* visible);

// Chains each kept Gaussian's summed 2D gradient (grad2d row n, stride
// kTileGradHead + 4 + num_extra: d mean (2), d conic (3), d opacity, d r,
// g, b, depth, extras) to its attributes, writing every value of `out` and
// of d_extra ([n][e]); culled Gaussians get zeros.
void ProjectBackward(const ProjectionInput& in, int count, int num_extra,
                     const int* tiles, const double* grad2d,
                     const ProjectionGradients& out, double* d_extra);

// Scratch of the binning, reused from frame to frame.
struct BinScratch {
  DeviceBuffer<int> offsets;  // per Gaussian: its first entry
  DeviceBuffer<uint64_t> keys, sorted_keys;
  DeviceBuffer<int> values;
  DeviceBuffer<char> cub;  // CUB's temporary storage
};

// Lists every tile's Gaussians front to back: one entry per (Gaussian,
// tile), key tile << 32 | depth bits, radix sorted (stable, so equal
// depths stay in index order, as the CPU sorts). Afterwards entries
// [ranges[2t], ranges[2t + 1]) of *gaussians are tile t's Gaussian indices.
// Returns the number of entries.
int BinGaussians(int count, int tiles_x, int tiles_y,
                 const ProjectedGaussian* projected, const int* tiles,
                 BinScratch* scratch, DeviceBuffer<int>* gaussians,
                 int* ranges);

// What both tile passes read. Images are row-major floats, H x W (x
// channels); gradient images may be nullptr (zero).
struct TileArgs {
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  int num_extra = 0;
  float background[3] = {0, 0, 0};
  const int* ranges = nullptr;     // per tile, BinGaussians
  const int* gaussians = nullptr;  // per entry
  const ProjectedGaussian* projected = nullptr;
  const float* features = nullptr;  // 4 + num_extra per Gaussian
  // Forward outputs; t_final and last are the backward's inputs.
  float* rgb = nullptr;
  float* alpha = nullptr;
  float* depth = nullptr;
  float* extra = nullptr;
  float* t_final = nullptr;  // transmittance after the last Gaussian
  int* last = nullptr;       // entries of the pixel's list used + 1
  // Backward: image gradients in, per-Gaussian 2D gradients summed into
  // grad2d (stride kTileGradHead + 4 + num_extra; zero it first).
  const float* d_rgb = nullptr;
  const float* d_alpha = nullptr;
  const float* d_depth = nullptr;
  const float* d_extra = nullptr;
  double* grad2d = nullptr;
};

void RasterizeForward(const TileArgs& args);
void RasterizeBackward(const TileArgs& args);

// DeviceRasterizer::Radii and Mean2dGradients into device arrays
// (screen_stats.cu): radii[n] = projected[n].radius; mean2d_grads[2n, 2n+1]
// = grad2d row n's d mean (stride as RasterizeBackward's), 0 where
// tiles[n] is 0.
void CopyRadii(int count, const ProjectedGaussian* projected, int* radii);
void CopyMean2dGradients(int count, const int* tiles, const double* grad2d,
                         int stride, double* mean2d_grads);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_CUDA_RASTER_KERNELS_H_
