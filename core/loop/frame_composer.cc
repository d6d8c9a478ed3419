#include "core/loop/frame_composer.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/loop/cycle_time.h"
#include "core/profile/stage_profile.h"

namespace es {
namespace {

// SH coefficients per channel that D offsets: its 16, or fewer when the
// model's degree has fewer.
int OffsetShCoeffs(int sh_degree) {
  return std::min(NumShCoeffs(sh_degree), (kResidualDim - kResidualSh) / 3);
}

// The view's ascending dynamic indices (num_dynamic() of them).
const int* DynamicIndices(const LoopStructure& s) {
  CHECK(s.dynamic_index != nullptr) << "LoopStructure without a dynamic set";
  return s.dynamic_index->data();
}

}  // namespace

LoopModelView LoopModelView::Of(const LoopModel& model) {
  LoopModelView v;
  v.structure = LoopStructure::Of(model);
  v.canonical = SplatView::Of(model.gaussians);
  if (model.motion) v.motion_params = model.motion->params();
  if (model.residual) v.residual_params = model.residual->params();
  return v;
}

FrameComposer::FrameComposer(const EulerOptions& euler_options)
    : euler_options_(euler_options) {}

EulerChain* FrameComposer::ChainFor(const MotionField* field) {
  if (!chain_ || chain_field_ != field) {
    chain_.emplace(field, euler_options_);
    chain_field_ = field;
  }
  return &*chain_;
}

const SplatView& FrameComposer::Compose(const LoopModelView& model,
                                        int frame) {
  ScopedStage timer(Stage::kComposition);
  const LoopStructure& s = model.structure;
  const int* dynamic = DynamicIndices(s);
  CHECK(s.start_times != nullptr);
  CHECK_EQ(static_cast<int>(s.start_times->size()), s.num_dynamic());
  const int* start_times = s.start_times->data();
  const int m = s.num_dynamic();
  CHECK_GT(s.cycle_length, 0);
  canonical_.resize(3 * static_cast<size_t>(m));
  cycle_index_.resize(m);
  cycle_number_.resize(m);
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    std::copy(model.canonical.means + 3 * n, model.canonical.means + 3 * n + 3,
              &canonical_[3 * k]);
    cycle_index_[k] =
        CycleIndex(frame, start_times[k], s.cycle_length);
    cycle_number_[k] =
        CycleNumber(frame, start_times[k], s.cycle_length);
  }
  positions_.resize(canonical_.size());
  euler_stats_ = EulerStats();
  if (s.motion != nullptr && m > 0) {
    EulerChain* chain = ChainFor(s.motion);
    chain->Forward(model.motion_params, m, canonical_.data(),
                   cycle_index_.data(), positions_.data());
    euler_stats_ = chain->stats();
  } else {
    positions_ = canonical_;
  }
  backward_ready_ = true;
  return Assemble(model);
}

const SplatView& FrameComposer::ComposeAdvected(const LoopModelView& model,
                                                const double* positions,
                                                const int* cycle_indices,
                                                int cycle_number) {
  ScopedStage timer(Stage::kComposition);
  const LoopStructure& s = model.structure;
  const int* dynamic = DynamicIndices(s);
  const int m = s.num_dynamic();
  canonical_.resize(3 * static_cast<size_t>(m));
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    std::copy(model.canonical.means + 3 * n, model.canonical.means + 3 * n + 3,
              &canonical_[3 * k]);
  }
  positions_.assign(positions, positions + 3 * static_cast<size_t>(m));
  cycle_index_.assign(cycle_indices, cycle_indices + m);
  cycle_number_.assign(m, cycle_number);
  euler_stats_ = EulerStats();
  backward_ready_ = false;
  return Assemble(model);
}

const SplatView& FrameComposer::Assemble(const LoopModelView& model) {
  const LoopStructure& s = model.structure;
  const int* dynamic = DynamicIndices(s);
  const SplatView& c = model.canonical;
  const int m = s.num_dynamic();
  const int count = c.count;
  const int coeffs = NumShCoeffs(c.sh_degree);
  view_ = c;
  if (m == 0) {
    residuals_.clear();
    return view_;
  }
  means_.assign(c.means, c.means + 3 * static_cast<size_t>(count));
  for (int k = 0; k < m; ++k) {
    std::copy(&positions_[3 * k], &positions_[3 * k] + 3,
              &means_[3 * dynamic[k]]);
  }
  view_.means = means_.data();
  if (s.residual == nullptr) {
    residuals_.clear();
    return view_;
  }
  residuals_.resize(static_cast<size_t>(m) * kResidualDim);
  s.residual->Evaluate(model.residual_params, m, canonical_.data(),
                           cycle_index_.data(), cycle_number_.data(),
                           residuals_.data(), &residual_ws_);
  opacity_logits_.assign(c.opacity_logits, c.opacity_logits + count);
  sh_.assign(c.sh, c.sh + 3 * static_cast<size_t>(coeffs) * count);
  const int offset_coeffs = OffsetShCoeffs(c.sh_degree);
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    const double* d = &residuals_[static_cast<size_t>(k) * kResidualDim];
    for (int j = 0; j < 3; ++j) means_[3 * n + j] += d[kResidualPosition + j];
    opacity_logits_[n] += d[kResidualOpacity];
    double* sh = &sh_[3 * static_cast<size_t>(n) * coeffs];
    for (int i = 0; i < 3 * offset_coeffs; ++i) sh[i] += d[kResidualSh + i];
  }
  view_.opacity_logits = opacity_logits_.data();
  view_.sh = sh_.data();
  return view_;
}

void FrameComposer::Backward(const LoopModelView& model,
                             const SplatGradients& grads,
                             const double* d_residuals,
                             const LoopModelGradients& out) {
  ScopedStage timer(Stage::kComposition);
  const LoopStructure& s = model.structure;
  const int* dynamic = DynamicIndices(s);
  const SplatView& c = model.canonical;
  const int m = s.num_dynamic();
  const int count = c.count;
  const size_t sh_size =
      3 * static_cast<size_t>(NumShCoeffs(c.sh_degree)) * count;
  CHECK(backward_ready_ && static_cast<int>(cycle_index_.size()) == m)
      << "FrameComposer::Backward without a matching Compose";
  auto add = [](const std::vector<double>& g, size_t n, double* dst) {
    if (dst == nullptr) return;
    CHECK_EQ(g.size(), n);
    for (size_t i = 0; i < n; ++i) dst[i] += g[i];
  };
  // Opacity, SH, scales and rotations pass D's additive offsets unchanged.
  add(grads.log_scales, 3 * static_cast<size_t>(count), out.log_scales);
  add(grads.quats, 4 * static_cast<size_t>(count), out.quats);
  add(grads.opacity_logits, count, out.opacity_logits);
  add(grads.sh, sh_size, out.sh);
  if (m == 0) {
    add(grads.means, 3 * static_cast<size_t>(count), out.means);
    return;
  }
  // Static means pass through; dynamic ones are routed below.
  d_positions_.resize(3 * static_cast<size_t>(m));
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    std::copy(&grads.means[3 * n], &grads.means[3 * n] + 3,
              &d_positions_[3 * k]);
  }
  if (out.means != nullptr) {
    int next = 0;
    for (int n = 0; n < count; ++n) {
      if (next < m && dynamic[next] == n) {
        ++next;
        continue;
      }
      for (int j = 0; j < 3; ++j)
        out.means[3 * n + j] += grads.means[3 * n + j];
    }
  }
  d_x0_.assign(3 * static_cast<size_t>(m), 0.0);
  if (s.residual != nullptr) {
    const int coeffs = NumShCoeffs(c.sh_degree);
    const int offset_coeffs = OffsetShCoeffs(c.sh_degree);
    d_residuals_.assign(static_cast<size_t>(m) * kResidualDim, 0.0);
    for (int k = 0; k < m; ++k) {
      const int n = dynamic[k];
      double* d = &d_residuals_[static_cast<size_t>(k) * kResidualDim];
      for (int j = 0; j < 3; ++j)
        d[kResidualPosition + j] = grads.means[3 * n + j];
      d[kResidualOpacity] = grads.opacity_logits[n];
      const double* g = &grads.sh[3 * static_cast<size_t>(n) * coeffs];
      for (int i = 0; i < 3 * offset_coeffs; ++i) d[kResidualSh + i] = g[i];
    }
    if (d_residuals != nullptr) {
      for (size_t i = 0; i < d_residuals_.size(); ++i)
        d_residuals_[i] += d_residuals[i];
    }
    s.residual->Backward(model.residual_params, d_residuals_.data(),
                             out.residual,
                             out.means != nullptr ? d_x0_.data() : nullptr,
                             &residual_ws_);
  }
  if (s.motion != nullptr) {
    CHECK(chain_ && chain_field_ == s.motion);
    chain_->Backward(model.motion_params, d_positions_.data(), out.motion,
                     out.means != nullptr ? d_x0_.data() : nullptr);
  } else {
    for (size_t i = 0; i < d_x0_.size(); ++i) d_x0_[i] += d_positions_[i];
  }
  if (out.means == nullptr) return;
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    for (int j = 0; j < 3; ++j) out.means[3 * n + j] += d_x0_[3 * k + j];
  }
}

}  // namespace es
