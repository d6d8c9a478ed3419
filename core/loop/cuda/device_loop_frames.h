#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_FRAMES_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_FRAMES_H_

// LoopFrames on the device: DeviceLoopRenderer plays and renders each
// frame (the rasterizer's float path); only the finished RGB image comes
// back to the host. Failures throw CudaError.

#include <vector>

#include <Eigen/Core>

#include "core/loop/cuda/device_loop_renderer.h"
#include "core/loop/loop_frames.h"

namespace es {
namespace cuda {

class DeviceLoopFrames : public LoopFrames {
 public:
  // Uploads the model, which must outlive the frames. Of RenderOptions
  // only the background applies: the device renders in float with its own
  // kernels (use_double and simd are the CPU rasterizer's).
  DeviceLoopFrames(const LoopModel* model, const RenderOptions& options)
      : renderer_(model), background_(options.background) {}

  void Start(int frame) override { renderer_.Start(frame); }
  void Advance() override { renderer_.Advance(); }
  const std::vector<double>& Rgb(const Camera& camera) override;
  const LoopRenderer* cpu_renderer() const override { return nullptr; }

 private:
  DeviceLoopRenderer renderer_;
  Eigen::Vector3d background_;
  std::vector<float> download_;
  std::vector<double> rgb_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_FRAMES_H_
