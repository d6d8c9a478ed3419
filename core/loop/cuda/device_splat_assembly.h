#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_SPLAT_ASSEMBLY_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_SPLAT_ASSEMBLY_H_

// A frame's splats on the device from the canonical ones and the dynamic
// Gaussians' positions at that frame: D evaluated at (x0, t, p) and
// ComposeDynamicKernel writing the dynamic entries into copies of the
// canonical arrays. The step DeviceFrameComposer (training) and
// DeviceLoopRenderer (the loop) share; each advects in its own way.

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_residual_field.h"
#include "core/fields/residual_field.h"
#include "core/loop/cuda/compose_kernels.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_splats.h"

namespace es {
namespace cuda {

// Where D's outputs sit in its rows, for the composition kernels.
inline constexpr ResidualLayout kResidualLayout{
    kResidualDim, kResidualPosition, kResidualOpacity, kResidualSh};

// The m dynamic Gaussians of one frame; device arrays.
struct DeviceDynamicFrame {
  int count = 0;
  const int* index = nullptr;         // their Gaussians (m)
  const double* x0 = nullptr;         // canonical positions (m x 3): D's x0
  const double* positions = nullptr;  // at the frame (m x 3)
  const int* cycle_index = nullptr;   // t (m), for D
  const int* cycle_number = nullptr;  // p (m), for D
};

// Owns the frame's arrays; not thread-safe.
class DeviceSplatAssembly {
 public:
  // The frame's splats: means copied with the dynamic ones replaced by
  // `positions` plus D's offsets; with D (residual non-null) also opacity
  // and SH copied and offset. Other arrays point at the canonical ones.
  // The view stays valid until the next Assemble.
  const DeviceSplatView& Assemble(const DeviceSplatView& canonical,
                                  const DeviceDynamicFrame& dynamic,
                                  const DeviceResidualField* residual,
                                  const FieldParams& residual_params);

  // D's outputs of the last Assemble (m x kResidualDim), nullptr without D.
  const double* residuals() const {
    return has_residuals_ ? residuals_.data() : nullptr;
  }
  // The workspace of D's last Evaluate, for its Backward.
  DeviceFieldWorkspace* residual_workspace() { return &residual_ws_; }

 private:
  bool has_residuals_ = false;
  DeviceFieldWorkspace residual_ws_;
  DeviceBuffer<double> residuals_, means_, opacity_logits_, sh_;
  DeviceSplatView view_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_SPLAT_ASSEMBLY_H_
