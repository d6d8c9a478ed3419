#include "solvers/train/cuda/device_joint_trainer.h"

#include <glog/logging.h>

#include <cmath>
#include <utility>

#include "core/model/dynamic_set.h"
#include "core/base/stage_profile.h"
#include "costs/cuda/splat_cost_kernels.h"
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
    : frames_(frames),
      train_(std::move(train)),
      options_(options),
      use_masks_(options.mask_weight > 0 && AllHaveMasks(*frames, train_)),
      energy_masks_(WaterLossOn(options) && AllHaveMasks(*frames, train_)),
      extent_(CameraExtent(*frames, train_)),
      sampler_(train_, options.seed),
      rng_(options.seed + 1),
      images_(*frames, train_, use_masks_ || energy_masks_),
      cost_(JointLossTerms(options, use_masks_), options.background,
            &rasterizer_, options.euler),
      // Its own rasterizer: both renders are kept until both backward
      // passes.
      pair_cost_(JointLossTerms(options, use_masks_), options.background,
                 &pair_rasterizer_, options.euler),
      guard_("Stage 3 training", options.max_nonfinite_steps) {
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
  if (LoopTextureOn(options_)) {
    loop_cost_.emplace(ImageGradientOnlyTerms(), options_.background,
                       &rasterizer_, options_.euler);
    loop_cost_->set_cycle_number(0);
    loop_texture_.emplace(LoopTextureOptions(options_));
  }
  if (PairLossOn(options_)) {
    partner_ = TrainingNeighbours(*frames_, train_);
    energy_.emplace(options_.water_energy);
    if (WaterTextureOn(options_)) texture_.emplace(options_.water_texture);
  }
  ApplyMotionRamp(options_, iteration_, &model_);
}

void DeviceJointTrainer::SetSceneFlowPrior(
    std::vector<SceneFlowSample> samples) {
  CHECK(model_.motion) << "a scene-flow prior needs the motion field";
  // The prior scores V itself, not its warmed-up displacement.
  MotionField unramped = *model_.motion;
  unramped.SetDisplacementFactor(1.0);
  prior_field_.emplace(unramped);
  flow_prior_.emplace(&*prior_field_, std::move(samples),
                      options_.flow_prior);
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
  const Frame& frame = (*frames_)[out.frame];
  cost_.Reset(frame.camera, images_.image(out.frame),
              use_masks_ ? images_.mask(out.frame) : nullptr,
              frame.time_index, Structure());
  // The splats' rows are cleared here, the fields' are zero already.
  grad_.ResizeZero(g_.size(), g_.sh_degree());
  const int partner = energy_ ? partner_[out.frame] : -1;
  if (partner >= 0) {
    out.loss = PairLossGradient(out.frame, partner, &out);
  } else {
    std::vector<double*> params = ParamBlocks();
    std::vector<double*> gradients = GradientBlocks(&grad_);
    out.loss = cost_.AddLossGradient(params.data(), gradients.data());
    out.photometric = cost_.last_photometric();
    out.mask = cost_.last_mask();
    out.residual = cost_.last_residual();
  }
  out.euler = cost_.last_euler_stats();
  if (loop_cost_) out.loss += LoopTextureGradient(out.frame, &out);
  if (flow_prior_) {
    // V's blocks come first among the fields.
    out.flow_prior = flow_prior_->AddLossAndGradient(
        {fields_[0].x.data(), fields_[1].x.data()}, iteration_,
        options_.iterations, options_.seed,
        {fields_[0].grad.data(), fields_[1].grad.data(), nullptr});
    out.loss += out.flow_prior;
  }
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
                   max_log_scale_.data(), params.log_scales);
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

double DeviceJointTrainer::PairLossGradient(int frame_index, int partner,
                                            JointIterationStats* out) {
  const Frame& frame = (*frames_)[frame_index];
  const Frame& other = (*frames_)[partner];
  out->pair_frame = partner;
  pair_cost_.Reset(other.camera, images_.image(partner),
                   use_masks_ ? images_.mask(partner) : nullptr,
                   other.time_index, Structure());
  pair_grad_.ResizeZero(g_.size(), g_.sh_degree());
  // Both backward passes add: the splats' rows (cleared) are averaged
  // below; the fields' rows are shared, take the sum of both passes and
  // are halved below.
  std::vector<double*> params = ParamBlocks();
  std::vector<double*> gradients = GradientBlocks(&grad_);
  std::vector<double*> pair_gradients = GradientBlocks(&pair_grad_);
  const double loss = cost_.RenderForGradient(params.data());
  const double pair_loss = pair_cost_.RenderForGradient(params.data());
  out->photometric =
      0.5 * (cost_.last_photometric() + pair_cost_.last_photometric());
  out->mask = 0.5 * (cost_.last_mask() + pair_cost_.last_mask());
  out->residual = 0.5 * (cost_.last_residual() + pair_cost_.last_residual());

  // The step follows 0.5 (loss + pair_loss + 2 energy): the energy's
  // gradient enters both backward passes at twice its weight and the sum
  // is halved below.
  const bool frame_first = frame.time_index < other.time_index;
  const int a = frame_first ? frame_index : partner;
  const int b = frame_first ? partner : frame_index;
  const DeviceJointRenderCost& first = frame_first ? cost_ : pair_cost_;
  const DeviceJointRenderCost& second = frame_first ? pair_cost_ : cost_;
  const Camera& camera = (*frames_)[a].camera;
  CHECK(camera.width == (*frames_)[b].camera.width &&
        camera.height == (*frames_)[b].camera.height)
      << "the water energy pairs frames of one size";
  const size_t values = 3 * static_cast<size_t>(camera.width) * camera.height;
  energy_grad_a_.Resize(values);
  energy_grad_a_.Zero();
  energy_grad_b_.Resize(values);
  energy_grad_b_.Zero();
  const double energy = energy_->Evaluate(
      first.render().rgb, second.render().rgb, images_.image(a),
      images_.image(b), energy_masks_ ? images_.mask(a) : nullptr,
      energy_masks_ ? images_.mask(b) : nullptr, camera.width, camera.height,
      2.0 * WaterLossRamp(options_, iteration_), energy_grad_a_.data(),
      energy_grad_b_.data(), &out->energy);
  const double texture = TextureLossGradient(
      first.render().rgb, second.render().rgb, a, b, out);
  cost_.BackwardWithImageGradient(
      params.data(),
      frame_first ? energy_grad_a_.data() : energy_grad_b_.data(),
      gradients.data(), /*accumulate=*/true);
  pair_cost_.BackwardWithImageGradient(
      params.data(),
      frame_first ? energy_grad_b_.data() : energy_grad_a_.data(),
      pair_gradients.data(), /*accumulate=*/true);
  const std::vector<int32_t>& sizes = cost_.layout().sizes();
  const size_t splat_blocks = sizes.size() - fields_.size();
  for (size_t k = 0; k < splat_blocks; ++k)
    AverageInto(sizes[k], pair_gradients[k], gradients[k]);
  for (FieldBlock& f : fields_)
    ScaleValues(static_cast<long long>(f.grad.size()), 0.5, f.grad.data());
  return 0.5 * (loss + pair_loss + energy + texture);
}

double DeviceJointTrainer::TextureLossGradient(const float* render_a,
                                               const float* render_b, int a,
                                               int b,
                                               JointIterationStats* out) {
  if (!texture_) return 0;
  // As JointTrainer's: each frame at full weight, the draws by iteration.
  const uint64_t draw = 2 * static_cast<uint64_t>(iteration_);
  const double ramp = WaterLossRamp(options_, iteration_);
  const double sum =
      HostTextureGradient(&*texture_, render_a, (*frames_)[a], ramp, draw,
                          energy_grad_a_.data()) +
      HostTextureGradient(&*texture_, render_b, (*frames_)[b], ramp, draw + 1,
                          energy_grad_b_.data());
  // The term itself, unramped (0 at iteration 0, where the ramp is).
  out->texture =
      ramp > 0 ? 0.5 * sum / (ramp * options_.water_texture.weight) : 0.0;
  return sum;
}

double DeviceJointTrainer::LoopTextureGradient(int frame_index,
                                               JointIterationStats* out) {
  const Frame& frame = (*frames_)[frame_index];
  loop_cost_->Reset(frame.camera, images_.image(frame_index), nullptr,
                    frame.time_index, Structure());
  std::vector<double*> params = ParamBlocks();
  loop_cost_->RenderForGradient(params.data());
  loop_grad_.Resize(3 * static_cast<size_t>(frame.camera.width) *
                    frame.camera.height);
  loop_grad_.Zero();
  const double ramp = WaterLossRamp(options_, iteration_);
  const double loss =
      HostTextureGradient(&*loop_texture_, loop_cost_->render().rgb, frame,
                          ramp, LoopTextureDraw(iteration_), loop_grad_.data());
  out->loop_texture =
      ramp > 0 ? loss / (ramp * options_.loop_texture_weight) : 0.0;
  std::vector<double*> gradients = GradientBlocks(&grad_);
  loop_cost_->BackwardWithImageGradient(params.data(), loop_grad_.data(),
                                        gradients.data(), /*accumulate=*/true);
  return loss;
}

double DeviceJointTrainer::HostTextureGradient(WaterTextureLoss* loss,
                                               const float* render,
                                               const Frame& frame,
                                               double scale, uint64_t draw,
                                               float* device_grad) {
  const size_t values =
      3 * static_cast<size_t>(frame.camera.width) * frame.camera.height;
  host_values_.resize(values);
  CopyToHost(host_values_.data(), render, values * sizeof(float));
  host_render_.assign(host_values_.begin(), host_values_.end());
  host_grad_.assign(values, 0.0);
  const double value =
      loss->Evaluate(host_render_.data(), frame.image,
                     energy_masks_ ? frame.mask : cv::Mat(), scale, draw,
                     host_grad_.data());
  // Up once, then added on the device.
  host_values_.assign(host_grad_.begin(), host_grad_.end());
  texture_grad_.Upload(host_values_);
  cuda::AddFloatArray(static_cast<long long>(values), texture_grad_.data(),
                      device_grad);
  return value;
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
    const Frame& frame = (*frames_)[f];
    cost_.Reset(frame.camera, images_.image(f),
                use_masks_ ? images_.mask(f) : nullptr, frame.time_index,
                Structure());
    cost_.AddLossGradient(params.data(), gradients.data());
    stats.AddView(frame.camera.width, frame.camera.height, rasterizer_);
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
  constexpr size_t kSplatBlocks = 6;
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
  if (flow_prior_) {
    // V's box may have changed: the prior's field is rebuilt in place
    // (flow_prior_ keeps pointing at it; same type, no const members).
    // The prior scores V itself, not its warmed-up displacement.
  MotionField unramped = *model_.motion;
  unramped.SetDisplacementFactor(1.0);
  prior_field_.emplace(unramped);
  }
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
