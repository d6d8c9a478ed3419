#ifndef EULERSPLAT_APPS_COMMON_IMAGE_RASTERIZER_ON_H_
#define EULERSPLAT_APPS_COMMON_IMAGE_RASTERIZER_ON_H_

// Host splats rendered on the device --device chose
// (apps/common/device_flag.h): CpuImageRasterizer or
// cuda::DeviceImageRasterizer.

#include <memory>

#include "apps/common/device_flag.h"
#include "core/render/image_rasterizer_factory.h"

namespace es {

std::unique_ptr<ImageRasterizer> ImageRasterizerOn(
    ComputeDevice device, const RenderOptions& options);
// The same as a factory, for the stages that make their own.
ImageRasterizerFactory ImageRasterizerOn(ComputeDevice device);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_IMAGE_RASTERIZER_ON_H_
