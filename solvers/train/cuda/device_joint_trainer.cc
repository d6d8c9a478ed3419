#include "solvers/train/cuda/device_joint_trainer.h"

#include <glog/logging.h>

#include <cmath>
#include <utility>

#include "core/model/dynamic_set.h"
#include "core/base/stage_profile.h"
#include "solvers/train/cuda/device_density_stats.h"
#include "solvers/train/cuda/training_kernels.h"
#include "solvers/train/joint_training_steps.h"
#include "solvers/train/water_particles.h"

namespace es {
namespace cuda {

DeviceJointTrainer::DeviceJointTrainer(const std::vector<Frame>* frames,
                                       std::vector<int> train,
                                       const JointTrainerOptions& options,
                                       GaussianSet initial,
                                       std::optional<MotionField> motion)
    : StageTrainerBase("Stage 3 training", frames, std::move(train), options),
      energy_masks_(WaterLossOn(options) && AllHaveMasks(*frames, train_)),
      sampler_(train_, options.seed),
      rng_(options.seed + 1),
      images_(*frames, train_, use_masks_ || energy_masks_),
      objective_(JointObjectiveOptionsOf(options, use_masks_, energy_masks_)) {
  model_ = InitialLoopModel(options_, static_cast<int>(frames_->size()),
                            std::move(initial), std::move(motion), &rng_);
  initial_dynamic_ = model_.num_dynamic();
  guarded_ = GuardedJointBlocks(options_, model_, extent_);
  fields_.resize(FieldParamBlocks(&model_).size());
  GaussianAdam adam;
  adam.Reset(model_.gaussians);
  UploadSplats(adam);
  UploadFields();
  for (FieldBlock& f : fields_) {
    f.m.Resize(f.x.size());
    f.m.Zero();
    f.v.Resize(f.x.size());
    f.v.Zero();
  }
  UpdateScaleBounds();
  if (PairLossOn(options_)) partner_ = TrainingNeighbours(*frames_, train_);
  ApplyMotionRamp(options_, iteration_, &model_);
}

void DeviceJointTrainer::SetSceneFlowPrior(
    std::vector<SceneFlowSample> samples) {
  CHECK(model_.motion) << "a scene-flow prior needs the motion field";
  objective_.SetSceneFlowPrior(*model_.motion, std::move(samples),
                               options_.flow_prior, options_.iterations,
                               options_.seed);
}

RenderOptions DeviceJointTrainer::render_options() const {
  return JointRenderOptions(options_);
}

LoopStructure DeviceJointTrainer::Structure() const {
  return LoopStructure::Of(model_);
}

std::vector<double*> DeviceJointTrainer::ParamBlocks() {
  std::vector<double*> blocks = g_.BlockPointers();
  for (FieldBlock& f : fields_) blocks.push_back(f.x.data());
  return blocks;
}

std::vector<double*> DeviceJointTrainer::GradientBlocks(
    DeviceGaussians* splat_grads) {
  std::vector<double*> blocks = splat_grads->BlockPointers();
  for (FieldBlock& f : fields_) blocks.push_back(f.grad.data());
  return blocks;
}

JointIterationStats DeviceJointTrainer::Step() {
  ScopedStage timer(Stage::kIteration);
  if (DynamicSetRefreshDue(options_, iteration_)) RefreshDynamicSet();
  JointIterationStats out;
  out.frame = sampler_.Next();
  out.num_dynamic = model_.num_dynamic();
  // The objective overwrites the splats' rows; the fields' are zero.
  grad_.ResizeZero(g_.size(), g_.sh_degree());
  if (PairLossOn(options_)) out.pair_frame = partner_[out.frame];
  const DeviceObjectiveFrame frame = ObjectiveFrame(out.frame);
  const DeviceObjectiveFrame partner =
      out.pair_frame >= 0 ? ObjectiveFrame(out.pair_frame) : frame;
  std::vector<double*> blocks = ParamBlocks();
  std::vector<double*> gradients = GradientBlocks(&grad_);
  out.loss = objective_.Evaluate(
      Structure(), blocks.data(), frame,
      out.pair_frame >= 0 ? &partner : nullptr,
      WaterLossRamp(options_, iteration_), iteration_, gradients.data(), &out);
  const bool finite =
      std::isfinite(out.loss) && GradientsFinite();
  if (!guard_.Accept(iteration_ + 1, finite)) {
    for (FieldBlock& f : fields_) f.grad.Zero();
    out.skipped = true;
    ++iteration_;
    ApplyMotionRamp(options_, iteration_, &model_);
    return out;
  }

  DeviceGaussianBlocks params = g_.Blocks();
  adam_.Step(ScheduledSplatRates(options_.splat_lr, extent_, iteration_,
                                 options_.iterations, use_masks_),
             grad_.Blocks(), params);
  if (options_.max_dynamic_pixels > 0) {
    ClampLogScales(model_.num_dynamic(), dynamic_index_.data(),
                   max_log_scale_.data(), params.arrays[kLogScalesArray]);
  }
  ++field_step_;
  const std::vector<double> lr =
      FieldLearningRates(options_, iteration_, model_);
  for (size_t b = 0; b < fields_.size(); ++b) {
    FieldBlock& f = fields_[b];
    // SparseAdam's update, value for value: untouched values of zero
    // moments stay as they are in both.
    DeviceAdamUpdate(AdamOptions(), field_step_, lr[b],
                     static_cast<int>(f.x.size()), f.grad.data(), f.m.data(),
                     f.v.data(), f.x.data());
    f.grad.Zero();
  }
  host_current_ = false;
  ++iteration_;
  ApplyMotionRamp(options_, iteration_, &model_);
  guard_.CheckBlocks(iteration_, guarded_, MaxMagnitudes());
  if (WaterDensifyDue(options_, iteration_, model_.num_dynamic()))
    out.densified = DensifyWaterNow();
  return out;
}

DeviceObjectiveFrame DeviceJointTrainer::ObjectiveFrame(int frame) const {
  return {&(*frames_)[frame], images_.image(frame), images_.mask(frame)};
}

void DeviceJointTrainer::RefreshDynamicSet() {
  FollowDynamicSet(
      options_,
      DynamicSet(g_.DownloadDynamicLogits(), options_.dynamic_threshold),
      &rng_, &model_);
  UpdateScaleBounds();
}

void DeviceJointTrainer::UpdateScaleBounds() {
  if (options_.max_dynamic_pixels <= 0) return;
  const LoopModel& current = model();  // the means, downloaded if stale
  const std::vector<double> max_scale =
      PixelSizeInWorld(current.gaussians, current.dynamic_index, *frames_,
                       train_, options_.max_dynamic_pixels);
  std::vector<double> max_log_scale(max_scale.size());
  for (size_t k = 0; k < max_scale.size(); ++k)
    max_log_scale[k] = std::log(max_scale[k]);
  dynamic_index_.Upload(current.dynamic_index);
  max_log_scale_.Upload(max_log_scale);
}

WaterDensifyResult DeviceJointTrainer::DensifyWaterNow() {
  ScopedPass pass(Pass::kDensify);  // its renders too
  ScopedStage timer(Stage::kDensify);
  const int budget = WaterBudget(options_, initial_dynamic_);
  if (model_.num_dynamic() >= budget) return {};  // skip the ranking pass
  // grad_ and the fields' gradients are scratch here: Step refills them.
  grad_.ResizeZero(g_.size(), g_.sh_degree());
  std::vector<double*> params = ParamBlocks();
  std::vector<double*> gradients = GradientBlocks(&grad_);
  DeviceDensityStats stats;
  stats.Reset(g_.size());
  for (int f : WaterDensifyViews(options_, train_, iteration_)) {
    const Camera& camera = (*frames_)[f].camera;
    objective_.FitGradient(Structure(), params.data(), ObjectiveFrame(f),
                           gradients.data());
    stats.AddView(camera.width, camera.height, objective_.rasterizer());
  }
  // Step expects the field gradients zero.
  for (FieldBlock& f : fields_) f.grad.Zero();
  DensityStats host_stats;
  stats.Download(&host_stats);
  std::vector<double> mean_grad;
  for (int i : model_.dynamic_index)
    mean_grad.push_back(host_stats.MeanGrad(i));
  GaussianAdam adam = DownloadState();
  const WaterDensifyResult result =
      DensifyRankedWater(options_, std::move(mean_grad), budget, iteration_,
                         *frames_, train_, &model_, &adam);
  if (result.split + result.cloned > 0) {
    UploadSplats(adam);
    UpdateScaleBounds();
  }
  return result;
}

bool DeviceJointTrainer::GradientsFinite() {
  flag_.Resize(1);
  flag_.Zero();
  grad_.MarkNonFinite(flag_.data());
  for (FieldBlock& f : fields_) {
    FlagNonFinite(static_cast<long long>(f.grad.size()), f.grad.data(),
                  flag_.data());
  }
  int flag = 0;
  flag_.Download(&flag);
  return flag == 0;
}

std::vector<double> DeviceJointTrainer::MaxMagnitudes() {
  constexpr size_t kSplatBlocks = kNumGaussianArrays;
  magnitude_bits_.Resize(kSplatBlocks + fields_.size());
  magnitude_bits_.Zero();
  g_.RaiseMaxMagnitudes(magnitude_bits_.data());
  for (size_t b = 0; b < fields_.size(); ++b) {
    RaiseMaxMagnitudeBits(static_cast<long long>(fields_[b].x.size()),
                          fields_[b].x.data(),
                          magnitude_bits_.data() + kSplatBlocks + b);
  }
  std::vector<double> magnitudes;
  for (unsigned long long bits : magnitude_bits_.Download())
    magnitudes.push_back(MagnitudeOfBits(bits));
  return magnitudes;
}

const LoopModel& DeviceJointTrainer::model() const {
  DownloadState();
  return model_;
}

GaussianAdam DeviceJointTrainer::DownloadState() const {
  if (!host_current_) {
    g_.Download(&model_.gaussians);
    std::vector<std::vector<double>*> blocks = FieldParamBlocks(&model_);
    for (size_t b = 0; b < blocks.size(); ++b)
      *blocks[b] = fields_[b].x.Download();
    host_current_ = true;
  }
  GaussianAdam adam;
  adam.Restore(adam_.State());
  return adam;
}

void DeviceJointTrainer::UploadSplats(const GaussianAdam& adam) {
  g_.Upload(model_.gaussians);
  adam_.Restore(adam.state());
}

void DeviceJointTrainer::UploadFields() {
  std::vector<std::vector<double>*> blocks = FieldParamBlocks(&model_);
  CHECK_EQ(blocks.size(), fields_.size());
  for (size_t b = 0; b < blocks.size(); ++b) {
    FieldBlock& f = fields_[b];
    f.x.Upload(*blocks[b]);
    f.grad.Resize(f.x.size());
    f.grad.Zero();
  }
}

JointCheckpoint DeviceJointTrainer::Save() const {
  GaussianAdam adam = DownloadState();
  std::vector<std::vector<double>> m, v;
  for (const FieldBlock& f : fields_) {
    m.push_back(f.m.Download());
    v.push_back(f.v.Download());
  }
  return PackJointCheckpoint(model_, iteration_, adam.state(), std::move(m),
                             std::move(v), field_step_, sampler_.state(),
                             rng_);
}

void DeviceJointTrainer::Restore(const JointCheckpoint& c,
                                 const std::string& source) {
  UnpackJointCheckpoint(c, source, &model_);
  iteration_ = c.iteration;
  ApplyMotionRamp(options_, iteration_, &model_);
  GaussianAdam adam;
  adam.Restore(c.adam);
  UploadSplats(adam);
  UploadFields();
  for (size_t b = 0; b < fields_.size(); ++b) {
    fields_[b].m.Upload(c.field_m[b]);
    fields_[b].v.Upload(c.field_v[b]);
  }
  host_current_ = true;
  UpdateScaleBounds();
  field_step_ = c.field_step;
  RestoreSamplerAndRng(c, source, &sampler_, &rng_);
  // V's box may have changed: the prior follows.
  if (objective_.has_scene_flow_prior())
    objective_.UpdateSceneFlowPriorField(*model_.motion);
}

LoopModel DeviceJointTrainer::FinalModel(int* pruned) const {
  return FinalLoopModel(model(), *frames_, pruned);
}

std::unique_ptr<JointStageTrainer> MakeDeviceJointTrainer(
    const std::vector<Frame>* frames, std::vector<int> train,
    const JointTrainerOptions& options, GaussianSet initial,
    std::optional<MotionField> motion) {
  return std::make_unique<DeviceJointTrainer>(
      frames, std::move(train), options, std::move(initial),
      std::move(motion));
}

}  // namespace cuda
}  // namespace es
