#include "core/loop/cuda/device_loop_renderer.h"

#include <glog/logging.h>

#include "core/loop/cycle_time.h"

namespace es {
namespace cuda {

DeviceLoopRenderer::DeviceLoopRenderer(const LoopModel* model,
                                       const EulerOptions& euler_options)
    : model_(model), num_dynamic_(model->num_dynamic()) {
  CHECK_EQ(static_cast<int>(model->start_times.size()), num_dynamic_)
      << "one start time per dynamic Gaussian";
  canonical_.Upload(SplatView::Of(model->gaussians));
  dynamic_index_.Upload(model->dynamic_index);
  std::vector<double> x0(3 * static_cast<size_t>(num_dynamic_));
  for (int k = 0; k < num_dynamic_; ++k) {
    const int g = model->dynamic_index[k];
    CHECK(g >= 0 && g < model->gaussians.size())
        << "dynamic index " << g << " is not a Gaussian";
    for (int j = 0; j < 3; ++j) {
      x0[3 * k + j] = model->gaussians.means[3 * g + j];
    }
  }
  x0_.Upload(x0);
  if (model->motion) {
    motion_.emplace(*model->motion);
    motion_params_.Upload(model->motion->params(),
                          model->motion->triplane().num_params(),
                          model->motion->mlp().num_params());
    animator_.emplace(&*motion_, euler_options, model->cycle_length);
  }
  if (model->residual) {
    residual_.emplace(*model->residual);
    residual_params_.Upload(model->residual->params(),
                            model->residual->triplane().num_params(),
                            model->residual->mlp().num_params());
    cycle_number_.Upload(std::vector<int>(num_dynamic_, 0));
  }
}

void DeviceLoopRenderer::Start(int frame) {
  frame_ = frame;
  started_ = true;
  if (animator_) {
    animator_->Start(motion_params_.params(), num_dynamic_, x0_.data(),
                     model_->start_times, frame);
    return;
  }
  cycle_index_.resize(num_dynamic_);
  for (int k = 0; k < num_dynamic_; ++k) {
    cycle_index_[k] =
        CycleIndex(frame, model_->start_times[k], model_->cycle_length);
  }
  cycle_index_device_.Upload(cycle_index_);
}

void DeviceLoopRenderer::Advance() {
  CHECK(started_) << "Start before Advance";
  ++frame_;
  if (animator_) {
    animator_->Advance(motion_params_.params());
    return;
  }
  for (int& t : cycle_index_) t = (t + 1) % model_->cycle_length;
  cycle_index_device_.Upload(cycle_index_);
}

const int* DeviceLoopRenderer::CycleIndices() const {
  return animator_ ? animator_->cycle_indices() : cycle_index_device_.data();
}

EulerStats DeviceLoopRenderer::euler_stats() const {
  return animator_ ? animator_->stats() : EulerStats();
}

const DeviceSplatView& DeviceLoopRenderer::Compose() {
  CHECK(started_) << "Start before Compose";
  const int m = num_dynamic_;
  DeviceDynamicFrame dynamic;
  if (m > 0) {
    dynamic = {m,
               dynamic_index_.data(),
               x0_.data(),
               animator_ ? animator_->positions() : x0_.data(),
               residual_ ? CycleIndices() : nullptr,
               cycle_number_.data()};
  }
  return assembly_.Assemble(canonical_.View(), dynamic,
                            residual_ ? &*residual_ : nullptr,
                            residual_params_.params());
}

const DeviceImages& DeviceLoopRenderer::Render(
    const Camera& camera, const Eigen::Vector3d& background) {
  return rasterizer_.ForwardDevice(camera, Compose(), background);
}

}  // namespace cuda
}  // namespace es
