#ifndef EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_FACTORY_H_
#define EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_FACTORY_H_

#include <functional>
#include <memory>

#include "core/render/image_rasterizer.h"
#include "core/render/rasterizer.h"

namespace es {

// Makes a rasterizer on some device: es_eval's stage takes one, and
// apps/common/image_rasterizer_on.h picks it by --device.
using ImageRasterizerFactory =
    std::function<std::unique_ptr<ImageRasterizer>(const RenderOptions&)>;

inline std::unique_ptr<ImageRasterizer> MakeCpuImageRasterizer(
    const RenderOptions& options) {
  return std::make_unique<CpuImageRasterizer>(options);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_FACTORY_H_
