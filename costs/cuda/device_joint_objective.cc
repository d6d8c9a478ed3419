#include "costs/cuda/device_joint_objective.h"

#include <glog/logging.h>

#include "costs/cuda/splat_cost_kernels.h"
#include "costs/splat_render_cost.h"

namespace es {
namespace cuda {

DeviceJointObjective::DeviceJointObjective(const JointObjectiveOptions& options)
    : options_(options),
      cost_(options.terms, options.render.background, &rasterizer_,
            options.euler),
      pair_cost_(options.terms, options.render.background, &pair_rasterizer_,
                 options.euler) {
  if (options_.loop_texture_on()) {
    loop_cost_.emplace(ImageGradientOnlyTerms(), options_.render.background,
                       &rasterizer_, options_.euler);
    loop_cost_->set_cycle_number(0);
    loop_texture_.emplace(options_.loop_texture());
  }
  if (options_.pair_on()) {
    energy_.emplace(options_.water_energy);
    if (options_.texture_on()) texture_.emplace(options_.water_texture);
  }
}

void DeviceJointObjective::Reset(DeviceJointRenderCost* cost,
                                 const DeviceObjectiveFrame& f,
                                 const LoopStructure& structure) {
  cost->Reset(f.frame->camera, f.image, cost->mask_on() ? f.mask : nullptr,
              f.frame->time_index, structure);
}

double DeviceJointObjective::Evaluate(const LoopStructure& structure,
                                      double const* const* params,
                                      const DeviceObjectiveFrame& frame,
                                      const DeviceObjectiveFrame* partner,
                                      double water_scale, int64_t iteration,
                                      double** gradients,
                                      JointObjectiveTerms* terms) {
  Reset(&cost_, frame, structure);
  // The costs add: the splats' rows are cleared here, the fields' are
  // zero already.
  const std::vector<int32_t>& sizes = cost_.layout().sizes();
  for (int b = 0; b < kNumSplatBlocks; ++b)
    DeviceZero(gradients[b], sizes[b] * sizeof(double));
  double loss;
  if (partner != nullptr) {
    CHECK(energy_) << "a partner frame needs a pair term";
    loss = PairLossGradient(structure, params, frame, *partner, water_scale,
                            iteration, gradients, terms);
  } else {
    loss = cost_.AddLossGradient(params, gradients);
    terms->photometric = cost_.last_photometric();
    terms->mask = cost_.last_mask();
    terms->residual = cost_.last_residual();
  }
  terms->euler = cost_.last_euler_stats();
  if (loop_cost_ && options_.loop_texture_due(iteration)) {
    loss += LoopTextureGradient(structure, params, frame, water_scale,
                                iteration, gradients, terms);
  }
  if (flow_prior_) {
    const int v = cost_.layout().motion_triplane();
    terms->flow_prior = flow_prior_->AddLossAndGradient(
        {params[v], params[v + 1]}, iteration, prior_iterations_, prior_seed_,
        {gradients[v], gradients[v + 1], nullptr});
    loss += terms->flow_prior;
  }
  return loss;
}

void DeviceJointObjective::SetSceneFlowPrior(
    const MotionField& motion, std::vector<SceneFlowSample> samples,
    const FlowPriorOptions& options, int64_t iterations, uint64_t seed) {
  UpdateSceneFlowPriorField(motion);
  flow_prior_.emplace(&*prior_field_, std::move(samples), options);
  prior_iterations_ = iterations;
  prior_seed_ = seed;
}

void DeviceJointObjective::UpdateSceneFlowPriorField(
    const MotionField& motion) {
  // Rebuilt in place: flow_prior_ keeps pointing at it.
  MotionField unramped = motion;
  unramped.SetDisplacementFactor(1.0);
  prior_field_.emplace(unramped);
}

double DeviceJointObjective::PairLossGradient(const LoopStructure& structure,
                                              double const* const* params,
                                              const DeviceObjectiveFrame& frame,
                                              const DeviceObjectiveFrame& other,
                                              double water_scale, int64_t draw,
                                              double** gradients,
                                              JointObjectiveTerms* terms) {
  Reset(&pair_cost_, other, structure);
  const std::vector<int32_t>& sizes = cost_.layout().sizes();
  // Both backward passes add: the splats' rows (cleared) are averaged
  // below; the fields' rows are shared, take the sum of both passes and
  // are halved below.
  pair_grad_.resize(kNumSplatBlocks);
  std::vector<double*> pair_gradients(gradients, gradients + sizes.size());
  for (int b = 0; b < kNumSplatBlocks; ++b) {
    pair_grad_[b].Resize(sizes[b]);
    pair_grad_[b].Zero();
    pair_gradients[b] = pair_grad_[b].data();
  }
  const double loss = cost_.RenderForGradient(params);
  const double pair_loss = pair_cost_.RenderForGradient(params);
  terms->photometric =
      0.5 * (cost_.last_photometric() + pair_cost_.last_photometric());
  terms->mask = 0.5 * (cost_.last_mask() + pair_cost_.last_mask());
  terms->residual = 0.5 * (cost_.last_residual() + pair_cost_.last_residual());

  // The step follows 0.5 (loss + pair_loss + 2 energy): the energy's
  // gradient enters both backward passes at twice its weight and the sum
  // is halved below.
  const bool frame_first = frame.frame->time_index < other.frame->time_index;
  const DeviceObjectiveFrame& a = frame_first ? frame : other;
  const DeviceObjectiveFrame& b = frame_first ? other : frame;
  const DeviceJointRenderCost& first = frame_first ? cost_ : pair_cost_;
  const DeviceJointRenderCost& second = frame_first ? pair_cost_ : cost_;
  const Camera& camera = a.frame->camera;
  CHECK(camera.width == b.frame->camera.width &&
        camera.height == b.frame->camera.height)
      << "the water energy pairs frames of one size";
  const size_t values = 3 * static_cast<size_t>(camera.width) * camera.height;
  energy_grad_a_.Resize(values);
  energy_grad_a_.Zero();
  energy_grad_b_.Resize(values);
  energy_grad_b_.Zero();
  const double energy = energy_->Evaluate(
      first.render().rgb, second.render().rgb, a.image, b.image, WaterMask(a),
      WaterMask(b), camera.width, camera.height, 2.0 * water_scale,
      energy_grad_a_.data(), energy_grad_b_.data(), &terms->energy);
  const double texture =
      TextureLossGradient(first.render().rgb, second.render().rgb, *a.frame,
                          *b.frame, water_scale, draw, terms);
  cost_.BackwardWithImageGradient(
      params, frame_first ? energy_grad_a_.data() : energy_grad_b_.data(),
      gradients, /*accumulate=*/true);
  pair_cost_.BackwardWithImageGradient(
      params, frame_first ? energy_grad_b_.data() : energy_grad_a_.data(),
      pair_gradients.data(), /*accumulate=*/true);
  for (int k = 0; k < kNumSplatBlocks; ++k)
    AverageInto(sizes[k], pair_gradients[k], gradients[k]);
  for (size_t k = kNumSplatBlocks; k < sizes.size(); ++k)
    ScaleArray(sizes[k], 0.5, gradients[k]);
  return 0.5 * (loss + pair_loss + energy + texture);
}

double DeviceJointObjective::TextureLossGradient(const float* render_a,
                                                 const float* render_b,
                                                 const Frame& a, const Frame& b,
                                                 double water_scale,
                                                 int64_t draw,
                                                 JointObjectiveTerms* terms) {
  if (!texture_) return 0;
  // As JointObjective's: each frame at full weight, the draws by `draw`.
  const double sum =
      HostTextureGradient(&*texture_, render_a, a, water_scale,
                          PairTextureDraw(draw, 0), energy_grad_a_.data()) +
      HostTextureGradient(&*texture_, render_b, b, water_scale,
                          PairTextureDraw(draw, 1), energy_grad_b_.data());
  terms->texture =
      UnrampedMean(sum, 2, water_scale, options_.water_texture.weight);
  return sum;
}

double DeviceJointObjective::LoopTextureGradient(
    const LoopStructure& structure, double const* const* params,
    const DeviceObjectiveFrame& frame, double water_scale, int64_t draw,
    double** gradients, JointObjectiveTerms* terms) {
  const Camera& camera = frame.frame->camera;
  loop_cost_->Reset(camera, frame.image, nullptr, frame.frame->time_index,
                    structure);
  loop_cost_->RenderForGradient(params);
  loop_grad_.Resize(3 * static_cast<size_t>(camera.width) * camera.height);
  loop_grad_.Zero();
  const double loss = HostTextureGradient(
      &*loop_texture_, loop_cost_->render().rgb, *frame.frame, water_scale,
      LoopTextureDraw(draw), loop_grad_.data());
  terms->loop_texture =
      UnrampedMean(loss, 1, water_scale,
                   options_.loop_texture_step_weight());
  loop_cost_->BackwardWithImageGradient(params, loop_grad_.data(), gradients,
                                        /*accumulate=*/true);
  return loss;
}

double DeviceJointObjective::HostTextureGradient(WaterTextureLoss* loss,
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
                     options_.water_masks ? frame.mask : cv::Mat(), scale, draw,
                     host_grad_.data());
  // Up once, then added on the device.
  host_values_.assign(host_grad_.begin(), host_grad_.end());
  texture_grad_.Upload(host_values_);
  AddFloatArray(static_cast<long long>(values), texture_grad_.data(),
                device_grad);
  return value;
}

double DeviceJointObjective::FitGradient(const LoopStructure& structure,
                                         double const* const* params,
                                         const DeviceObjectiveFrame& frame,
                                         double** gradients) {
  Reset(&cost_, frame, structure);
  return cost_.AddLossGradient(params, gradients);
}

}  // namespace cuda
}  // namespace es
