#ifndef EULERSPLAT_CORE_RENDER_CUDA_DEVICE_SPLATS_H_
#define EULERSPLAT_CORE_RENDER_CUDA_DEVICE_SPLATS_H_

// Splat attributes and their gradients in device memory, in the layouts of
// SplatView and SplatGradients (double): views for the device rasterizer,
// and owning copies of host arrays. No CUDA types.

#include "core/model/camera.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/project_kernels.h"
#include "core/render/rasterizer.h"
#include "core/render/splat_gradient_pointers.h"

namespace es {
namespace cuda {

// Device arrays of the splat attributes: a SplatView whose pointers are
// device memory (num_extra at most kMaxDeviceExtra, 4).
using DeviceSplatView = SplatView;

// Device arrays the backward writes (SplatGradients' layouts and sizes,
// double); every value is written.
struct DeviceSplatGradients : SplatGradientPointers {
  double* extra = nullptr;  // may be nullptr when num_extra is 0
};

// The projection kernels' view (project_kernels.h) of a camera and device
// splat arrays (MakeProjectionInput's, which only copies the pointers).
ProjectionInput DeviceProjectionInput(const Camera& camera,
                                      const DeviceSplatView& splats);

// Device copies of a splat set's arrays.
class DeviceSplats {
 public:
  void Upload(const SplatView& splats);
  DeviceSplatView View() const;

 private:
  DeviceSplatView view_;
  DeviceBuffer<double> means_, log_scales_, quats_, opacity_logits_, sh_,
      extra_;
};

// Device arrays for a splat set's gradients.
class DeviceGradientArrays {
 public:
  void Resize(int count, int sh_degree, int num_extra);
  DeviceSplatGradients View();
  // Copies every array into *grads (resized).
  void Download(SplatGradients* grads) const;

 private:
  DeviceBuffer<double> means_, log_scales_, quats_, opacity_logits_, sh_,
      extra_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_CUDA_DEVICE_SPLATS_H_
