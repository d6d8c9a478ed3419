#ifndef EULERSPLAT_CORE_RASTER_IO_H_
#define EULERSPLAT_CORE_RASTER_IO_H_

#include <string>

#include <Eigen/Core>

#include "core/camera.h"
#include "core/colmap_io.h"
#include "core/rasterizer.h"

namespace es {

// The camera of a registered COLMAP image. Only PINHOLE (fx fy cx cy) and
// SIMPLE_PINHOLE (f cx cy) are accepted: rendering does not undistort.
// Throws InputError naming `source` and the model otherwise.
Camera PinholeCameraFromColmap(const ColmapCamera& camera,
                               const ColmapImage& image,
                               const std::string& source);

// Parses "r,g,b" (three numbers); throws InputError naming `flag`.
Eigen::Vector3d ParseColor(const std::string& text, const std::string& flag);

// 8-bit RGB PNG, round(clamp(v, 0, 1) * 255). Throws InputError if the file
// cannot be written.
void WriteRgbPng(const RenderResult& result, const std::string& path);

// 16-bit gray PNG of the expected depth (depth / alpha) times `scale`,
// rounded and clamped to [0, 65535]; 0 where alpha <= 1e-3.
void WriteDepthPng(const RenderResult& result, double scale,
                   const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_RASTER_IO_H_
