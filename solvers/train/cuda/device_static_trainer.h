#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_STATIC_TRAINER_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_STATIC_TRAINER_H_

// StaticTrainer (solvers/train/static_trainer.h) on a CUDA device, step
// for step: the same frame order, SH-degree schedule, loss terms (through
// DeviceSplatRenderCost, a ceres::CostFunction on device blocks), learning
// rates, divergence guard and densification schedule. Parameters,
// gradients, Adam moments, densification statistics and the training
// images stay on the device; a step brings back only the loss's scalars
// and two finiteness flags. Raising the SH degree, densifying and
// resetting opacities (every few hundred steps) go through the host: the
// state is downloaded, edited by the CPU code and uploaded again.
// Checkpoints are the CPU trainer's, so either trainer resumes the other's.
// No CUDA types; failures throw CudaError.

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "core/io/scene.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "costs/cuda/device_splat_render_cost.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/cuda/device_adam.h"
#include "solvers/train/cuda/device_density_stats.h"
#include "solvers/train/cuda/device_frame_images.h"
#include "solvers/train/cuda/device_gaussians.h"
#include "solvers/train/densify.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/optim/frame_sampler.h"
#include "solvers/train/stage_trainer_base.h"
#include "solvers/train/static_stage.h"
#include "solvers/train/static_trainer.h"

namespace es {
namespace cuda {

class DeviceStaticTrainer
    : public StageTrainerBase<StaticStageTrainer, StaticTrainerOptions> {
 public:
  // Uploads the training frames' images (and masks, when the mask term is
  // on) once: device memory of 12 (+ 4) bytes per pixel per frame.
  DeviceStaticTrainer(const std::vector<Frame>* frames, std::vector<int> train,
                      const StaticTrainerOptions& options,
                      GaussianSet initial);

  IterationStats Step() override;

  // Downloads the parameters when a step changed them since the last call.
  const GaussianSet& gaussians() const override;
  double scene_extent() const override { return extent_; }
  RenderOptions render_options() const override;

  Checkpoint Save() const override;
  void Restore(const Checkpoint& checkpoint) override;

 private:
  // The host's copy of the state that densification and SH changes edit.
  struct HostState {
    GaussianSet g;
    GaussianAdam adam;
    DensityStats stats;
  };
  HostState Download() const;
  void Upload(const HostState& state);

  DeviceFrameImages images_;
  DeviceGaussians g_;
  DeviceGaussians grad_;
  DeviceGaussianAdam adam_;
  DeviceDensityStats stats_;
  FrameSampler sampler_;
  std::mt19937_64 rng_;
  DeviceRasterizer rasterizer_;  // the cost renders with it; densify reads it
  DeviceSplatRenderCost cost_;
  mutable GaussianSet host_g_;       // gaussians()'s copy
  mutable bool host_g_current_ = false;
};

// StaticTrainerFactory's device maker (solvers/train/static_stage.h): a
// device trainer on the scene's training split, seeded as
// MakeStaticTrainer seeds the CPU one. `scene` must outlive it.
std::unique_ptr<StaticStageTrainer> MakeDeviceStaticTrainer(
    const Scene& scene, const StaticTrainerOptions& options);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_STATIC_TRAINER_H_
