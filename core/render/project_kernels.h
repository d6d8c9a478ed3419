#ifndef EULERSPLAT_CORE_RENDER_PROJECT_KERNELS_H_
#define EULERSPLAT_CORE_RENDER_PROJECT_KERNELS_H_

// The per-Gaussian projection (3D -> 2D covariance, conic, SH colour, pixel
// and tile boxes) and its backward in float, a batch of Gaussians at a time
// with one SIMD lane per Gaussian. Compiled once per instruction set
// (project_kernels_{sse2,avx2,avx512}.cc from project_kernels_impl.h) and
// picked at run time like the tile kernels. The double reference is
// ProjectSplat / ProjectSplatBackward (raster_project.h): the rasterizer
// runs it with RenderOptions::use_double and these kernels otherwise.
// Plain types only: the per-instruction-set code includes nothing with
// inline library code.

#include "core/base/simd_level.h"

namespace es {

// One Gaussian after projection, everything the tile pass needs.
struct ProjectedSplat {
  double mean2d[2];  // continuous pixel coordinates
  double conic[3];   // inverse of the dilated 2D covariance: a, b, c
  double depth;      // camera z
  double opacity;
  double color[3];   // SH + 0.5, clamped below at 0
  int radius;        // ceil(3 sqrt(max eigenvalue)), px
  // Tiles [tile_x0, tile_x1) x [tile_y0, tile_y1) the Gaussian is binned to:
  // those its 3-sigma square touches and its pixel box reaches.
  int tile_x0, tile_x1, tile_y0, tile_y1;
  // Pixels [px0, px1) x [py0, py1) that can reach alpha >= kMinAlpha, with a
  // one-pixel margin; outside it the tile pass skips the Gaussian.
  int px0, px1, py0, py1;
};

// The camera and the splat arrays (SplatView's layouts) of a projection.
struct ProjectionInput {
  double R[9];  // world -> camera rotation, row-major
  double t[3];
  double center[3];  // camera center in world
  double fx, fy, cx, cy;
  double lim_x, lim_y;  // FOV clamp of x/z and y/z
  int width, height, tiles_x, tiles_y;
  int sh_degree;
  const double* means;           // 3N
  const double* log_scales;      // 3N
  const double* quats;           // 4N, w x y z
  const double* opacity_logits;  // N
  const double* sh;              // 3KN, [n][k][rgb]
};

// Where the backward writes (SplatGradients' arrays).
struct ProjectionGradients {
  double* means;
  double* log_scales;
  double* quats;
  double* opacity_logits;
  double* sh;
};

// Gaussians per kernel call: one AVX-512 vector of floats.
constexpr int kProjectBatch = 16;

struct ProjectKernelSet {
  // Projects Gaussians [begin, begin + count), count <= kProjectBatch:
  // keep[i] = whether Gaussian begin + i survives culling (as ProjectSplat
  // decides), and then out[i] its projection.
  void (*forward)(const ProjectionInput& in, int begin, int count,
                  ProjectedSplat* out, char* keep);
  // For those of Gaussians [begin, begin + count) with keep[i] set, chains
  // their summed 2D gradients (row i of grad2d, `stride` values: d mean2d
  // (2), d conic (3), d opacity, d r, g, b, depth, ...) to their means,
  // log-scales, quaternions, opacity logits and SH, writing (not adding)
  // those entries of *out.
  void (*backward)(const ProjectionInput& in, int begin, int count,
                   const char* keep, const double* grad2d, int stride,
                   const ProjectionGradients& out);
};

// The kernels for an instruction set (kAuto: the best the CPU has).
const ProjectKernelSet& ProjectKernels(SimdLevel level);

// One set per instruction set (internal to the dispatch).
namespace project_sse2 {
const ProjectKernelSet& Kernels();
}
namespace project_avx2 {
const ProjectKernelSet& Kernels();
}
namespace project_avx512 {
const ProjectKernelSet& Kernels();
}

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_PROJECT_KERNELS_H_
