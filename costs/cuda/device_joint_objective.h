#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_OBJECTIVE_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_OBJECTIVE_H_

// JointObjective (costs/joint_objective.h) on a CUDA device, term for term:
// each frame's fit by DeviceJointRenderCost, the pair's mean with
// DeviceWaterEnergyLoss across it, the texture terms (WaterTextureLoss on
// the host: each render and its gradient cross the bus once per step, in
// exchange for one implementation of its sorts) and the loop texture term.
// Parameters and gradients are device blocks in JointBlockLayout order.
// No CUDA types; failures throw CudaError.

#include <cstdint>
#include <optional>
#include <vector>

#include "core/base/cuda/device_buffer.h"
#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/fields/motion_field.h"
#include "core/render/cuda/device_rasterizer.h"
#include "costs/cuda/device_joint_render_cost.h"
#include "costs/cuda/device_scene_flow_prior.h"
#include "costs/cuda/device_water_energy_loss.h"
#include "costs/joint_objective_options.h"
#include "costs/water_texture_loss.h"

namespace es {
namespace cuda {

// A frame as the device objective reads it: the host frame (camera, time
// index; its image and mask for the host texture terms) and its device
// image (H W 3 floats) and mask (H W floats, nullable without masks).
struct DeviceObjectiveFrame {
  const Frame* frame = nullptr;
  const float* image = nullptr;
  const float* mask = nullptr;
};

// Reuses its buffers: not thread-safe.
class DeviceJointObjective {
 public:
  explicit DeviceJointObjective(const JointObjectiveOptions& options);

  const JointObjectiveOptions& options() const { return options_; }

  // JointObjective's scene-flow prior, on the device.
  void SetSceneFlowPrior(const MotionField& motion,
                         std::vector<SceneFlowSample> samples,
                         const FlowPriorOptions& options, int64_t iterations,
                         uint64_t seed);
  void UpdateSceneFlowPriorField(const MotionField& motion);
  bool has_scene_flow_prior() const { return flow_prior_.has_value(); }

  // JointObjective::Evaluate on device blocks: the splats' gradient rows
  // are overwritten, the fields' added to (the caller keeps them zero
  // between steps). Only the terms' sums come back.
  double Evaluate(const LoopStructure& structure, double const* const* params,
                  const DeviceObjectiveFrame& frame,
                  const DeviceObjectiveFrame* partner, double water_scale,
                  int64_t iteration, double** gradients,
                  JointObjectiveTerms* terms);

  // The frame's fit alone, its gradient added (+=) into `gradients`;
  // rasterizer() then holds its render's statistics (water
  // densification's ranking).
  double FitGradient(const LoopStructure& structure,
                     double const* const* params,
                     const DeviceObjectiveFrame& frame, double** gradients);
  const DeviceRasterizer& rasterizer() const { return rasterizer_; }

 private:
  void Reset(DeviceJointRenderCost* cost, const DeviceObjectiveFrame& f,
             const LoopStructure& structure);
  double PairLossGradient(const LoopStructure& structure,
                          double const* const* params,
                          const DeviceObjectiveFrame& frame,
                          const DeviceObjectiveFrame& other, double water_scale,
                          int64_t draw, double** gradients,
                          JointObjectiveTerms* terms);
  double TextureLossGradient(const float* render_a, const float* render_b,
                             const Frame& a, const Frame& b, double water_scale,
                             int64_t draw, JointObjectiveTerms* terms);
  double LoopTextureGradient(const LoopStructure& structure,
                             double const* const* params,
                             const DeviceObjectiveFrame& frame,
                             double water_scale, int64_t draw,
                             double** gradients, JointObjectiveTerms* terms);
  // `loss` of the device render of `frame` on the host, times `scale`;
  // its gradient goes up once and is added to `device_grad` (H W 3
  // floats). Returns the loss.
  double HostTextureGradient(WaterTextureLoss* loss, const float* render,
                             const Frame& frame, double scale, uint64_t draw,
                             float* device_grad);
  const float* WaterMask(const DeviceObjectiveFrame& f) const {
    return options_.water_masks ? f.mask : nullptr;
  }

  JointObjectiveOptions options_;
  // Two rasterizers: both renders of a pair are kept until both backward
  // passes.
  DeviceRasterizer rasterizer_, pair_rasterizer_;
  DeviceJointRenderCost cost_, pair_cost_;
  std::vector<DeviceBuffer<double>> pair_grad_;  // the partner's splat rows
  std::optional<DeviceWaterEnergyLoss> energy_;
  std::optional<WaterTextureLoss> texture_;
  DeviceBuffer<float> energy_grad_a_, energy_grad_b_;
  // The frame as the loop plays it (on rasterizer_, after cost_'s
  // backward pass), its loss and image gradient.
  std::optional<DeviceJointRenderCost> loop_cost_;
  std::optional<WaterTextureLoss> loop_texture_;
  DeviceBuffer<float> loop_grad_;
  // The texture terms' transfers.
  std::vector<float> host_values_;
  std::vector<double> host_render_, host_grad_;
  DeviceBuffer<float> texture_grad_;
  // The scene-flow prior, on a copy of V at full displacement.
  std::optional<DeviceMotionField> prior_field_;
  std::optional<DeviceSceneFlowPrior> flow_prior_;
  int64_t prior_iterations_ = 0;
  uint64_t prior_seed_ = 0;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_JOINT_OBJECTIVE_H_
