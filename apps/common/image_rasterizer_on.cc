#include "apps/common/image_rasterizer_on.h"

#ifdef ES_HAVE_CUDA
#include "core/render/cuda/device_image_rasterizer.h"
#endif

namespace es {

std::unique_ptr<ImageRasterizer> ImageRasterizerOn(
    ComputeDevice device, const RenderOptions& options) {
#ifdef ES_HAVE_CUDA
  if (device == ComputeDevice::kCuda)
    return std::make_unique<cuda::DeviceImageRasterizer>(options);
#else
  (void)device;  // ParseDeviceFlag refuses cuda in such a build
#endif
  return MakeCpuImageRasterizer(options);
}

ImageRasterizerFactory ImageRasterizerOn(ComputeDevice device) {
  return [device](const RenderOptions& options) {
    return ImageRasterizerOn(device, options);
  };
}

}  // namespace es
