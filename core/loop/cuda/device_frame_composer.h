#ifndef EULERSPLAT_CORE_LOOP_CUDA_DEVICE_FRAME_COMPOSER_H_
#define EULERSPLAT_CORE_LOOP_CUDA_DEVICE_FRAME_COMPOSER_H_

// FrameComposer's training path (Compose at frame i and its Backward,
// core/loop/frame_composer.h) on the device: the dynamic Gaussians are
// advected from their canonical positions by DeviceEulerChain to their
// cycle index, D is evaluated at (x0, t, p) by DeviceResidualField, and
// the frame's splats are assembled by ComposeDynamicKernel; the backward
// maps d loss / d composed splats to the canonical blocks, V's and D's
// parameters, all on the device. Only the small per-frame cycle arrays
// cross (to the device, and only when they change) and the Euler chain's
// two counts come back. No CUDA types; failures throw CudaError.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/fields/cuda/device_residual_field.h"
#include "core/loop/cuda/device_euler_chain.h"
#include "core/loop/cuda/device_splat_assembly.h"
#include "core/loop/euler_chain.h"
#include "core/loop/frame_composer.h"
#include "core/loop/loop_model.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_splats.h"

namespace es {
namespace cuda {

// LoopModelView's parameter values as device arrays: the canonical splats
// (extra passed through) and V's and D's blocks (when the structure has
// them).
struct DeviceLoopModelView {
  DeviceSplatView canonical;
  FieldParams motion_params;
  FieldParams residual_params;
};

// Keeps its state between Compose and Backward: not thread-safe.
class DeviceFrameComposer {
 public:
  explicit DeviceFrameComposer(const EulerOptions& euler_options = {});

  // Points the composer at a model shape (the structure's vectors and
  // fields must outlive the calls that follow). Cheap when nothing
  // changed: the dynamic set is uploaded only when it differs from the
  // last one, and V's and D's device fields are rebuilt only when the
  // field object, its parameter counts, its box or its output scale
  // changed.
  void SetStructure(const LoopStructure& structure);

  // Frame i's splats (FrameComposer::Compose): t = CycleIndex(i, t0, L)
  // Euler steps of V from x0, plus D(x0, t, p = CycleNumber(i, t0, L)),
  // or with `cycle_number` D at that p for every Gaussian (0: the loop as
  // Alg. 2 plays it). The view stays valid until the next Compose;
  // log-scales, quaternions and extra point at the canonical arrays.
  const DeviceSplatView& Compose(
      const DeviceLoopModelView& model, int frame,
      std::optional<int> cycle_number = std::nullopt);

  // Backward of the last Compose (same values): grads (device, the
  // composed splats' d loss, every array but extra read) to the canonical
  // blocks (the dynamic means through D's dependence on x0 and through the
  // Euler chain), V's and D's parameters. d_residuals (device, num_dynamic
  // x kResidualDim, nullable) is added to the gradient of D's outputs.
  // `out` points at device memory (its triplane_chunks must be null).
  void Backward(const DeviceLoopModelView& model,
                const DeviceSplatGradients& grads, const double* d_residuals,
                const LoopModelGradients& out);

  int num_dynamic() const { return num_dynamic_; }
  // D's outputs of the last Compose (device, num_dynamic x kResidualDim);
  // nullptr without a residual field.
  const double* residuals() const { return assembly_.residuals(); }
  // Euler-chain counts of the last Compose.
  const EulerStats& euler_stats() const { return euler_stats_; }

 private:
  // What a device field is built from, to see when it must be rebuilt.
  struct FieldKey {
    const void* field = nullptr;
    int triplane_params = 0, mlp_params = 0;
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    double scale = 0;
    bool operator==(const FieldKey& o) const {
      return field == o.field && triplane_params == o.triplane_params &&
             mlp_params == o.mlp_params && lo == o.lo && hi == o.hi &&
             scale == o.scale;
    }
  };
  static FieldKey KeyOf(const MotionField* field);
  static FieldKey KeyOf(const ResidualField* field);
  // Frame i's cycle indices and numbers (or `cycle_number` for all) from
  // the host start times, uploaded when they changed.
  void SetFrame(int frame, std::optional<int> cycle_number);

  EulerOptions euler_options_;
  LoopStructure structure_;
  int num_dynamic_ = 0;
  bool backward_ready_ = false;
  EulerStats euler_stats_;
  // The dynamic set and, per Gaussian, its place in it (-1: static).
  std::vector<int> dynamic_host_;
  int slot_count_ = -1;
  DeviceBuffer<int> dynamic_, slot_;
  FieldKey motion_key_, residual_key_;
  std::optional<DeviceMotionField> motion_;
  std::optional<DeviceEulerChain> chain_;
  std::optional<DeviceResidualField> residual_;
  // The current frame's cycle indices (the chain's host steps) and
  // numbers, with their device copies for D.
  std::vector<int> cycle_index_, cycle_number_;
  bool cycles_uploaded_ = false;
  DeviceBuffer<int> cycle_index_device_, cycle_number_device_;
  DeviceBuffer<double> x0_, positions_;
  DeviceSplatAssembly assembly_;  // the frame's splats and D's outputs
  DeviceBuffer<double> d_positions_, d_residuals_, d_x0_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_DEVICE_FRAME_COMPOSER_H_
