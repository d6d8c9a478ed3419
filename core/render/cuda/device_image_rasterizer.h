#ifndef EULERSPLAT_CORE_RENDER_CUDA_DEVICE_IMAGE_RASTERIZER_H_
#define EULERSPLAT_CORE_RENDER_CUDA_DEVICE_IMAGE_RASTERIZER_H_

// ImageRasterizer (core/render/image_rasterizer.h) on the device: each
// call uploads the host's splats, renders them with DeviceRasterizer (its
// float path; of RenderOptions only the background applies) and brings the
// images back. Failures throw CudaError.

#include "core/render/cuda/device_rasterizer.h"
#include "core/render/image_rasterizer.h"

namespace es {
namespace cuda {

using DeviceImageRasterizer = ImageRasterizerWith<DeviceRasterizer>;

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_CUDA_DEVICE_IMAGE_RASTERIZER_H_
