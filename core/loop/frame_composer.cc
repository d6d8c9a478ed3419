#include "core/loop/frame_composer.h"

#include <algorithm>

#include <glog/logging.h>
#include <omp.h>

#include "core/loop/cycle_time.h"
#include "core/base/stage_profile.h"

namespace es {
namespace {

// Fewest dynamic Gaussians per share: below it a thread's batches are too
// small to pay for the parallel region and the gradient sum.
constexpr int kMinSharePoints = 64;

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

void FrameComposer::PlanShares(const LoopStructure& s, int m, bool advect) {
  const bool motion = advect && s.motion != nullptr;
  // Work per Gaussian in MLP parameters: V's per Euler step, D's once.
  const double v_cost = motion ? s.motion->mlp().num_params() : 0.0;
  const double d_cost =
      s.residual != nullptr ? s.residual->mlp().num_params() : 0.0;
  double total = 0.0;
  for (int k = 0; k < m; ++k) total += cycle_index_[k] * v_cost + d_cost;
  int shares = omp_in_parallel() ? 1 : omp_get_max_threads();
  if (max_shares_ > 0) shares = std::min(shares, max_shares_);
  shares = std::min(shares, m / kMinSharePoints);
  if (!(total > 0.0)) shares = 1;
  shares = std::max(shares, 1);
  if (static_cast<int>(shares_.size()) < shares) shares_.resize(shares);
  num_shares_ = shares;
  int k = 0;
  double done = 0.0;
  for (int g = 0; g < shares; ++g) {
    Share& share = shares_[g];
    share.begin = k;
    if (g + 1 == shares) {
      k = m;
    } else {
      // At least one Gaussian each, and one left for every later share.
      const double target = total * (g + 1) / shares;
      const int last = m - (shares - 1 - g);
      while (k < last && (k == share.begin || done < target)) {
        done += cycle_index_[k] * v_cost + d_cost;
        ++k;
      }
    }
    share.end = k;
  }
}

template <typename Run>
void FrameComposer::RunShares(const Run& run) {
  if (num_shares_ == 1) {
    run(0);
    return;
  }
#pragma omp parallel for schedule(static, 1) num_threads(num_shares_)
  for (int g = 0; g < num_shares_; ++g) run(g);
}

void FrameComposer::ResidualOnShare(const LoopModelView& model, int g) {
  Share& share = shares_[g];
  const int b = share.begin, n = share.end - share.begin;
  model.structure.residual->Evaluate(
      model.residual_params, n, &canonical_[3 * b], &cycle_index_[b],
      &cycle_number_[b], &residuals_[static_cast<size_t>(b) * kResidualDim],
      &share.residual_ws);
}

void FrameComposer::EvaluateResidual(const LoopModelView& model) {
  ScopedStage timer(Stage::kFieldsForward);
  if (model.structure.num_dynamic() == 0) return;
  RunShares([&](int g) { ResidualOnShare(model, g); });
}

void FrameComposer::EvaluateFields(const LoopModelView& model, bool advect) {
  ScopedStage timer(Stage::kFieldsForward);
  const LoopStructure& s = model.structure;
  const int m = s.num_dynamic();
  const bool motion = advect && s.motion != nullptr;
  advected_ = motion;
  if (s.residual != nullptr) {
    residuals_.resize(static_cast<size_t>(m) * kResidualDim);
  } else {
    residuals_.clear();
  }
  euler_stats_ = EulerStats();
  if (m == 0 || (!motion && s.residual == nullptr)) return;
  PlanShares(s, m, advect);
  auto run = [&](int g) {
    Share& share = shares_[g];
    const int b = share.begin, n = share.end - share.begin;
    share.stats = EulerStats();
    if (motion) {
      if (!share.chain || share.chain_field != s.motion) {
        share.chain.emplace(s.motion, euler_options_);
        share.chain_field = s.motion;
      }
      share.chain->Forward(model.motion_params, n, &canonical_[3 * b],
                           &cycle_index_[b], &positions_[3 * b]);
      share.stats = share.chain->stats();
    }
    if (s.residual != nullptr) ResidualOnShare(model, g);
  };
  RunShares(run);
  for (int g = 0; g < num_shares_; ++g) {
    const EulerStats& e = shares_[g].stats;
    euler_stats_.velocity_evaluations += e.velocity_evaluations;
    euler_stats_.nonfinite_velocities += e.nonfinite_velocities;
    euler_stats_.clamped_steps += e.clamped_steps;
  }
}

const SplatView& FrameComposer::Compose(const LoopModelView& model,
                                        int frame,
                                        std::optional<int> cycle_number) {
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
    cycle_number_[k] = cycle_number ? *cycle_number
                                    : CycleNumber(frame, start_times[k],
                                                  s.cycle_length);
  }
  // The Euler chain overwrites these when there is a motion field.
  positions_ = canonical_;
  EvaluateFields(model, /*advect=*/true);
  backward_ready_ = true;
  return Assemble(model);
}

const SplatView& FrameComposer::Recompose(const LoopModelView& model,
                                          int cycle_number) {
  ScopedStage timer(Stage::kComposition);
  const LoopStructure& s = model.structure;
  const int m = s.num_dynamic();
  CHECK(backward_ready_ && static_cast<int>(cycle_index_.size()) == m)
      << "FrameComposer::Recompose without a matching Compose";
  cycle_number_.assign(m, cycle_number);
  // positions_ still holds the chain's output; D alone is evaluated.
  if (s.residual != nullptr) EvaluateResidual(model);
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
  EvaluateFields(model, /*advect=*/false);
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
  if (m == 0) return view_;
  means_.assign(c.means, c.means + 3 * static_cast<size_t>(count));
  for (int k = 0; k < m; ++k) {
    std::copy(&positions_[3 * k], &positions_[3 * k] + 3,
              &means_[3 * dynamic[k]]);
  }
  view_.means = means_.data();
  if (s.residual == nullptr) return view_;
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
  }
  if (advected_ || s.residual != nullptr) {
    FieldsBackward(model, out);
  } else {
    for (size_t i = 0; i < d_x0_.size(); ++i) d_x0_[i] += d_positions_[i];
  }
  if (out.means == nullptr) return;
  for (int k = 0; k < m; ++k) {
    const int n = dynamic[k];
    for (int j = 0; j < 3; ++j) out.means[3 * n + j] += d_x0_[3 * k + j];
  }
}

void FrameComposer::FieldsBackward(const LoopModelView& model,
                                   const LoopModelGradients& out) {
  ScopedStage timer(Stage::kFieldsBackward);
  const LoopStructure& s = model.structure;
  CHECK(num_shares_ >= 1 &&
        shares_[num_shares_ - 1].end == s.num_dynamic())
      << "FrameComposer::Backward without a matching Compose";
  const bool motion = advected_;
  for (int g = 1; g < num_shares_; ++g) {
    Share& share = shares_[g];
    if (motion) {
      share.motion_grads.Resize(s.motion->triplane().num_params(),
                                s.motion->mlp().num_params());
    }
    if (s.residual != nullptr) {
      share.residual_grads.Resize(s.residual->triplane().num_params(),
                                  s.residual->mlp().num_params());
    }
  }
  // D, then V through the Euler chain, each share into its own gradient
  // buffers (the first into out's); dL/dx0 rows are the share's own.
  auto run = [&](int g) {
    Share& share = shares_[g];
    const int b = share.begin, n = share.end - share.begin;
    double* d_x0 = out.means != nullptr ? &d_x0_[3 * b] : nullptr;
    if (s.residual != nullptr) {
      const FieldGradients grads =
          g == 0 ? out.residual : share.residual_grads.Gradients(out.residual);
      s.residual->Backward(model.residual_params,
                           &d_residuals_[static_cast<size_t>(b) * kResidualDim],
                           grads, d_x0, &share.residual_ws);
    }
    if (motion) {
      CHECK(share.chain && share.chain_field == s.motion);
      const FieldGradients grads =
          g == 0 ? out.motion : share.motion_grads.Gradients(out.motion);
      share.chain->Backward(model.motion_params, &d_positions_[3 * b], grads,
                            d_x0);
    } else {
      for (int i = 3 * b; i < 3 * (b + n); ++i) d_x0_[i] += d_positions_[i];
    }
  };
  if (num_shares_ == 1) {
    run(0);
    return;
  }
#pragma omp parallel for schedule(static, 1) num_threads(num_shares_)
  for (int g = 0; g < num_shares_; ++g) run(g);
  std::vector<FieldGradientBuffer*>& buffers = gradient_buffers_;
  if (motion) {
    buffers.clear();
    for (int g = 1; g < num_shares_; ++g)
      buffers.push_back(&shares_[g].motion_grads);
    AddAndClearGradients(buffers, out.motion);
  }
  if (s.residual != nullptr) {
    buffers.clear();
    for (int g = 1; g < num_shares_; ++g)
      buffers.push_back(&shares_[g].residual_grads);
    AddAndClearGradients(buffers, out.residual);
  }
}

}  // namespace es
