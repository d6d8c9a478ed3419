#include "core/loop/loop_renderer.h"

#include <glog/logging.h>

#include "core/loop/cycle_time.h"

namespace es {

LoopRenderer::LoopRenderer(const LoopModel* model,
                           const RenderOptions& options,
                           const EulerOptions& euler_options)
    : model_(model),
      options_(options),
      view_(LoopModelView::Of(*model)),
      composer_(euler_options) {
  const int n = model->num_dynamic();
  CHECK_EQ(static_cast<int>(model->start_times.size()), n);
  canonical_.resize(3 * static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int g = model->dynamic_index[k];
    for (int j = 0; j < 3; ++j) {
      canonical_[3 * k + j] = model->gaussians.means[3 * g + j];
    }
  }
  if (model->motion) {
    animator_.emplace(&*model->motion, euler_options, model->cycle_length);
  }
}

void LoopRenderer::Start(int frame) {
  frame_ = frame;
  started_ = true;
  const int n = model_->num_dynamic();
  if (animator_) {
    animator_->Start(model_->motion->params(), n, canonical_.data(),
                     model_->start_times, frame);
    return;
  }
  cycle_index_.resize(n);
  for (int k = 0; k < n; ++k) {
    cycle_index_[k] =
        CycleIndex(frame, model_->start_times[k], model_->cycle_length);
  }
}

void LoopRenderer::Advance() {
  CHECK(started_) << "Start before Advance";
  ++frame_;
  if (animator_) {
    animator_->Advance(model_->motion->params());
    return;
  }
  for (int& t : cycle_index_) t = (t + 1) % model_->cycle_length;
}

const std::vector<double>& LoopRenderer::positions() const {
  return animator_ ? animator_->positions() : canonical_;
}

const std::vector<int>& LoopRenderer::cycle_indices() const {
  return animator_ ? animator_->cycle_indices() : cycle_index_;
}

EulerStats LoopRenderer::euler_stats() const {
  return animator_ ? animator_->stats() : EulerStats();
}

const SplatView& LoopRenderer::Compose() {
  CHECK(started_) << "Start before Compose";
  return composer_.ComposeAdvected(view_, positions().data(),
                                   cycle_indices().data(), /*cycle_number=*/0);
}

const RenderResult& LoopRenderer::Render(const Camera& camera) {
  rasterizer_.Forward(camera, Compose(), options_, &result_);
  return result_;
}

}  // namespace es
