#ifndef EULERSPLAT_CORE_VIZ_RENDER_PNG_H_
#define EULERSPLAT_CORE_VIZ_RENDER_PNG_H_

#include <string>

#include "core/render/rasterizer.h"

namespace es {

// 8-bit RGB PNG, round(clamp(v, 0, 1) * 255). Throws InputError if the file
// cannot be written.
void WriteRgbPng(const RenderResult& result, const std::string& path);

// 16-bit gray PNG of the expected depth (depth / alpha) times `scale`,
// rounded and clamped to [0, 65535]; 0 where alpha <= 1e-3.
void WriteDepthPng(const RenderResult& result, double scale,
                   const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_RENDER_PNG_H_
