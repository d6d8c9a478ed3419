#ifndef EULERSPLAT_CORE_RENDER_CUDA_DEVICE_RASTERIZER_H_
#define EULERSPLAT_CORE_RENDER_CUDA_DEVICE_RASTERIZER_H_

// The rasterizer on a CUDA device: the same projection, culling, binning,
// compositing and gradients as es::Rasterizer's float path
// (core/render/rasterizer.h), with the same conventions. No CUDA types
// here: host code that is not compiled by nvcc includes it and links
// es_cuda (built when CMake finds the CUDA toolkit; ES_HAVE_CUDA is defined
// then). Every CUDA failure throws CudaError (cuda_error.h).

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/base/cuda/cuda_error.h"
#include "core/render/cuda/device_splats.h"
#include "core/render/rasterizer.h"

namespace es {
namespace cuda {

// The images of the last forward, in device memory owned by the
// rasterizer: RenderResult's layouts and meanings, in float.
struct DeviceImages {
  int width = 0, height = 0, num_extra = 0;
  const float* rgb = nullptr;    // H*W*3, background included
  const float* alpha = nullptr;  // H*W
  const float* depth = nullptr;  // H*W
  const float* extra = nullptr;  // H*W*E
};

// Device image gradients (float, DeviceImages' layouts; nullptr: zero).
struct DeviceImageGradients {
  const float* d_rgb = nullptr;
  const float* d_alpha = nullptr;
  const float* d_depth = nullptr;
  const float* d_extra = nullptr;
};

// Like Rasterizer, Backward must follow Forward on the same object, with
// the splat arrays alive and unchanged in between.
class DeviceRasterizer {
 public:
  DeviceRasterizer();
  ~DeviceRasterizer();
  DeviceRasterizer(const DeviceRasterizer&) = delete;
  DeviceRasterizer& operator=(const DeviceRasterizer&) = delete;

  // Host arrays in and out (copied to and from the device): Rasterizer's
  // interface. Of the options only the background applies: the device
  // always runs the float path.
  void Forward(const Camera& camera, const SplatView& splats,
               const RenderOptions& options, RenderResult* result);
  void Backward(const RenderGradients& image_grads, SplatGradients* grads);

  // Device arrays in and out: nothing but a few scalars crosses to the
  // host. The images stay valid until the next forward.
  const DeviceImages& ForwardDevice(const Camera& camera,
                                    const DeviceSplatView& splats,
                                    const Eigen::Vector3d& background);
  void BackwardDevice(const DeviceImageGradients& image_grads,
                      const DeviceSplatGradients& grads);

  // Gaussians that survived culling in the last forward.
  int num_visible() const;
  // (Gaussian, tile) pairs the last forward binned.
  int num_entries() const;
  // As Rasterizer's: per input Gaussian its screen radius (0 if culled)
  // from the last forward, and d loss / d projected mean (2N, 0 if culled)
  // from the last backward.
  void Radii(std::vector<int>* radii) const;
  void Mean2dGradients(std::vector<double>* grads) const;
  // The same into device arrays of N ints and 2N doubles (every value
  // written), for statistics that stay on the device.
  void RadiiDevice(int* radii) const;
  void Mean2dGradientsDevice(double* grads) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_CUDA_DEVICE_RASTERIZER_H_
