#ifndef EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_H_
#define EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_H_

// Splats made on the host rendered into host images, on the CPU
// (CpuImageRasterizer: Rasterizer) or a GPU (cuda::DeviceImageRasterizer,
// core/render/cuda/device_image_rasterizer.h): how es_eval renders Alg.
// 1's compositions on the device --device chose.

#include "core/model/camera.h"
#include "core/render/rasterizer.h"

namespace es {

class ImageRasterizer {
 public:
  virtual ~ImageRasterizer() = default;

  // `splats` seen from `camera`, background included; valid until the
  // next call.
  virtual const RenderResult& Render(const Camera& camera,
                                     const SplatView& splats) = 0;
};

// An ImageRasterizer around a rasterizer with Rasterizer's host Forward,
// given the same options on every call.
template <typename R>
class ImageRasterizerWith : public ImageRasterizer {
 public:
  explicit ImageRasterizerWith(const RenderOptions& options)
      : options_(options) {}

  const RenderResult& Render(const Camera& camera,
                             const SplatView& splats) override {
    rasterizer_.Forward(camera, splats, options_, &result_);
    return result_;
  }

 private:
  RenderOptions options_;
  R rasterizer_;
  RenderResult result_;
};

using CpuImageRasterizer = ImageRasterizerWith<Rasterizer>;

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_IMAGE_RASTERIZER_H_
