#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_JOINT_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_JOINT_TRAINER_H_

// JointTrainer (solvers/train/joint_trainer.h) on a CUDA device, step for
// step: the same frame order, start times, objective (through
// DeviceJointObjective, JointObjective's twin on device blocks), water
// energy pairs, scene-flow prior, learning rates, divergence guard and
// water densification (the host-side pieces are the CPU trainer's own,
// solvers/train/joint_training_steps.h). The splats, V's and D's
// parameters, their gradients and Adam moments and the training images
// stay on the device; a step brings back only the loss's scalars and the
// finiteness flags. The dynamic set's refresh (every refresh_interval
// steps) downloads the dynamic logits; water densification (every few
// tens of steps, first half) and checkpoints go through the host.
// Checkpoints are the CPU trainer's, so either trainer resumes the
// other's. No CUDA types; failures throw CudaError.

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/fields/cuda/device_motion_field.h"
#include "core/io/scene.h"
#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/device_joint_objective.h"
#include "solvers/optim/cuda/device_adam.h"
#include "solvers/train/cuda/device_frame_images.h"
#include "solvers/train/cuda/device_gaussians.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/joint_stage_trainer.h"
#include "solvers/train/stage_trainer_base.h"

namespace es {
namespace cuda {

class DeviceJointTrainer
    : public StageTrainerBase<JointStageTrainer, JointTrainerOptions> {
 public:
  // As JointTrainer's; uploads the training frames' images (and masks,
  // when a term uses them) once.
  DeviceJointTrainer(const std::vector<Frame>* frames, std::vector<int> train,
                     const JointTrainerOptions& options, GaussianSet initial,
                     std::optional<MotionField> motion);

  void SetSceneFlowPrior(std::vector<SceneFlowSample> samples) override;
  bool has_flow_prior() const override {
    return objective_.has_scene_flow_prior();
  }

  JointIterationStats Step() override;

  // Downloads the parameters when a step changed them since the last call.
  const LoopModel& model() const override;
  LoopModel FinalModel(int* pruned = nullptr) const override;
  RenderOptions render_options() const override;

  JointCheckpoint Save() const override;
  void Restore(const JointCheckpoint& checkpoint,
               const std::string& source) override;

 private:
  // One field block (V's triplane or MLP, D's triplane or MLP) on the
  // device: values, gradient (zero between steps) and Adam moments.
  struct FieldBlock {
    DeviceBuffer<double> x, grad, m, v;
  };

  // The model's parameters, Adam moments (splats' and fields') to and
  // from the host copy model_ (whose structure is always current).
  // DownloadState brings model_'s values up to date (when a step changed
  // them) and returns the splats' Adam state.
  GaussianAdam DownloadState() const;
  void UploadSplats(const GaussianAdam& adam);
  // The field values from model_, their gradients zero.
  void UploadFields();
  void RefreshDynamicSet();
  // The per-Gaussian bounds of max_dynamic_pixels for the current set
  // (needs model_'s means current), uploaded with the dynamic indices.
  void UpdateScaleBounds();
  // The splat and field blocks in JointBlockLayout order.
  std::vector<double*> ParamBlocks();
  std::vector<double*> GradientBlocks(DeviceGaussians* splat_grads);
  // Frame `frame` (an index into frames_) as the objective reads it.
  DeviceObjectiveFrame ObjectiveFrame(int frame) const;
  WaterDensifyResult DensifyWaterNow();
  // Whether every value of the splats' and the fields' gradients is
  // finite: one flag for all, one int back to the host.
  bool GradientsFinite();
  // MaxMagnitude of each block GuardedJointBlocks lists (splats, then the
  // fields' values): one download.
  std::vector<double> MaxMagnitudes();
  LoopStructure Structure() const;

  bool energy_masks_ = false;
  FrameSampler sampler_;
  std::mt19937_64 rng_;
  // The model's structure (dynamic set, start times, fields' shapes and
  // boxes, Gaussian count); its values are current only when
  // host_current_.
  mutable LoopModel model_;
  mutable bool host_current_ = true;
  int initial_dynamic_ = 0;
  DeviceFrameImages images_;
  DeviceGaussians g_, grad_;
  DeviceGaussianAdam adam_;
  std::vector<FieldBlock> fields_;
  int64_t field_step_ = 0;
  DeviceBuffer<int> dynamic_index_;        // for the scale bound
  DeviceBuffer<double> max_log_scale_;     // per dynamic Gaussian
  DeviceBuffer<int> flag_;
  DeviceBuffer<unsigned long long> magnitude_bits_;
  // The loss and gradient of a step (the sampled frame, its partner).
  DeviceJointObjective objective_;
  // Each training frame's neighbour for the pair terms (-1: none).
  std::vector<int> partner_;
};

// The device trainer behind an interface, for callers that choose the
// device at run time.
std::unique_ptr<JointStageTrainer> MakeDeviceJointTrainer(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_JOINT_TRAINER_H_
