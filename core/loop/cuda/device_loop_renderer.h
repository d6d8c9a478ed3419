#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_RENDERER_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_RENDERER_H_

// LoopRenderer (core/loop/loop_renderer.h) on the device: Alg. 2 moves the
// dynamic Gaussians one Euler step per frame (DeviceLoopAnimator), D is
// applied at cycle number p = 0 (DeviceResidualField), the frame's splats
// are composed as FrameComposer::ComposeAdvected does and rendered with
// DeviceRasterizer::ForwardDevice. Everything per frame stays on the
// device. A model without V keeps its dynamic Gaussians at their
// canonical positions; without D there are no offsets. No CUDA types;
// failures throw CudaError.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/fields/cuda/device_motion_field.h"
#include "core/fields/cuda/device_residual_field.h"
#include "core/loop/cuda/device_loop_animator.h"
#include "core/loop/cuda/device_splat_assembly.h"
#include "core/loop/euler_chain.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "core/render/cuda/device_splats.h"

namespace es {
namespace cuda {

class DeviceLoopRenderer {
 public:
  // Uploads the model's Gaussians and field parameters; the model must
  // outlive the renderer and keep its values (a change is not seen).
  DeviceLoopRenderer(const LoopModel* model,
                     const EulerOptions& euler_options = {});

  void Start(int frame);
  void Advance();
  int frame() const { return frame_; }

  // The current frame's splats on the device, every offset applied; valid
  // until the next Compose or Render.
  const DeviceSplatView& Compose();
  // Renders the current frame (the rasterizer's float path); the images
  // stay valid until the next call.
  const DeviceImages& Render(const Camera& camera,
                             const Eigen::Vector3d& background);

  // Euler-step counts since Start.
  EulerStats euler_stats() const;

 private:
  // The current cycle indices (device, one per dynamic Gaussian).
  const int* CycleIndices() const;

  const LoopModel* model_;
  int num_dynamic_;
  int frame_ = 0;
  bool started_ = false;
  DeviceSplats canonical_;
  DeviceBuffer<int> dynamic_index_;
  DeviceBuffer<double> x0_;  // dynamic canonical positions
  std::optional<DeviceMotionField> motion_;
  std::optional<DeviceResidualField> residual_;
  DeviceFieldBlocks motion_params_, residual_params_;
  std::optional<DeviceLoopAnimator> animator_;  // absent without V
  std::vector<int> cycle_index_;                // without V, on the host
  DeviceBuffer<int> cycle_index_device_, cycle_number_;  // without V; p = 0
  DeviceSplatAssembly assembly_;  // the frame's splats and D's outputs
  DeviceRasterizer rasterizer_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_LOOP_RENDERER_H_
