#ifndef EULERSPLAT_CORE_RENDER_RASTER_CONSTANTS_H_
#define EULERSPLAT_CORE_RENDER_RASTER_CONSTANTS_H_

namespace es {

// Conventions shared with the 3DGS / gsplat ecosystem (see docs/DESIGN.md).
// Plain constants, no includes: the per-instruction-set tile kernels
// (tile_kernels_impl.h) include this and nothing with inline code.
constexpr double kCovarianceDilation = 0.3;   // px^2 added to the 2D covariance
constexpr double kNearPlane = 0.01;           // cull z <= this
constexpr double kMaxAlpha = 0.99;            // keeps 1 - alpha invertible
constexpr double kMinAlpha = 1.0 / 255.0;     // below one 8-bit level: skip
constexpr double kMinTransmittance = 1e-4;    // stop before T falls below
constexpr int kTileSize = 16;

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RASTER_CONSTANTS_H_
