#include "costs/scene_flow_cost.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

#include "core/base/stage_profile.h"

namespace es {
namespace {

// d -= (d . u) u: the part of d that a sample with unseen direction u
// (|u| <= 1) constrains, the component along u scaled by 1 - |u|^2.
// P = I - u u^T is symmetric, so the gradient of 0.5 |P d|^2 with respect
// to d is P (P d); P is idempotent only for a unit or zero u.
void ProjectOutUnseen(const double* u, double* d) {
  const double along = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
  for (int c = 0; c < 3; ++c) d[c] -= along * u[c];
}

}  // namespace

void SceneFlowBatch::Assign(const std::vector<SceneFlowSample>& samples,
                            const std::vector<int>& indices) {
  x.resize(3 * indices.size());
  target.resize(3 * indices.size());
  unseen.resize(3 * indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    const SceneFlowSample& s = samples[indices[k]];
    for (int c = 0; c < 3; ++c) {
      x[3 * k + c] = s.x[c];
      target[3 * k + c] = s.v[c];
      unseen[3 * k + c] = s.unseen[c];
    }
  }
}

void SceneFlowBatch::AssignAll(const std::vector<SceneFlowSample>& samples) {
  std::vector<int> all(samples.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  Assign(samples, all);
}

SceneFlowCost::SceneFlowCost(const MotionField* field,
                             const SceneFlowBatch* batch, double eps)
    : field_(field), batch_(batch), eps_(eps) {
  CHECK(field != nullptr && batch != nullptr);
  CHECK_GT(eps, 0.0);
  set_num_residuals(1);
  mutable_parameter_block_sizes()->push_back(field->triplane().num_params());
  mutable_parameter_block_sizes()->push_back(field->mlp().num_params());
}

double SceneFlowCost::Loss(const FieldParams& params,
                           const FieldGradients& grads) const {
  ScopedStage timer(Stage::kSceneFlow);
  const int n = batch_->size();
  if (n == 0) return 0.0;
  velocity_.resize(3 * n);
  d_velocity_.resize(3 * n);
  field_->Evaluate(params, n, batch_->x.data(), velocity_.data(),
                   &workspace_);
  double sum = 0;
  for (int s = 0; s < n; ++s) {
    double d[3];
    for (int c = 0; c < 3; ++c) {
      d[c] = velocity_[3 * s + c] - batch_->target[3 * s + c];
    }
    ProjectOutUnseen(&batch_->unseen[3 * s], d);
    for (int c = 0; c < 3; ++c) sum += d[c] * d[c];
    // dl/dV(x_s) = P_s P_s (V(x_s) - V'(x_s)) / n.
    ProjectOutUnseen(&batch_->unseen[3 * s], d);
    for (int c = 0; c < 3; ++c) d_velocity_[3 * s + c] = d[c] / n;
  }
  if (grads.triplane != nullptr || grads.mlp != nullptr) {
    field_->Backward(params, d_velocity_.data(), grads, nullptr, &workspace_);
  }
  return 0.5 * sum / n;
}

bool SceneFlowCost::Evaluate(double const* const* parameters,
                             double* residuals, double** jacobians) const {
  const FieldParams params{parameters[0], parameters[1]};
  FieldGradients grads;
  if (jacobians != nullptr) {
    if (jacobians[0] != nullptr) {
      std::fill_n(jacobians[0], parameter_block_sizes()[0], 0.0);
      grads.triplane = jacobians[0];
    }
    if (jacobians[1] != nullptr) {
      std::fill_n(jacobians[1], parameter_block_sizes()[1], 0.0);
      grads.mlp = jacobians[1];
    }
  }
  const double loss = Loss(params, grads);
  if (!std::isfinite(loss)) return false;
  const double r = std::sqrt(2.0 * loss + eps_);
  residuals[0] = r;
  // dr/dtheta = (dl/dtheta) / r.
  for (int b = 0; b < 2; ++b) {
    if (jacobians == nullptr || jacobians[b] == nullptr) continue;
    const int size = parameter_block_sizes()[b];
    for (int i = 0; i < size; ++i) jacobians[b][i] /= r;
  }
  return true;
}

SceneFlowResiduals::SceneFlowResiduals(const MotionField* field,
                                       const SceneFlowBatch* batch)
    : field_(field), batch_(batch) {
  CHECK(field != nullptr && batch != nullptr);
  CHECK_GT(batch->size(), 0);
  set_num_residuals(3 * batch->size());
  mutable_parameter_block_sizes()->push_back(field->triplane().num_params());
  mutable_parameter_block_sizes()->push_back(field->mlp().num_params());
}

bool SceneFlowResiduals::Evaluate(double const* const* parameters,
                                  double* residuals,
                                  double** jacobians) const {
  const int n = batch_->size();
  CHECK_EQ(3 * n, num_residuals()) << "batch size changed";
  const FieldParams params{parameters[0], parameters[1]};
  const int sizes[2] = {parameter_block_sizes()[0],
                        parameter_block_sizes()[1]};
  const bool any_jacobian =
      jacobians != nullptr &&
      (jacobians[0] != nullptr || jacobians[1] != nullptr);
  for (int b = 0; b < 2 && any_jacobian; ++b) {
    if (jacobians[b] != nullptr) {
      std::fill_n(jacobians[b], 3 * n * sizes[b], 0.0);
    }
  }
  // One sample at a time, so each backward pass fills one Jacobian row.
  for (int s = 0; s < n; ++s) {
    double v[3];
    field_->Evaluate(params, 1, &batch_->x[3 * s], v, &workspace_);
    const double* u = &batch_->unseen[3 * s];
    for (int c = 0; c < 3; ++c) v[c] -= batch_->target[3 * s + c];
    ProjectOutUnseen(u, v);
    for (int c = 0; c < 3; ++c) {
      residuals[3 * s + c] = v[c];
      if (!std::isfinite(residuals[3 * s + c])) return false;
    }
    if (!any_jacobian) continue;
    for (int c = 0; c < 3; ++c) {
      // Row c of P_s J_V: the backward of P_s's row c (P is symmetric).
      double d_v[3] = {0, 0, 0};
      d_v[c] = 1.0;
      ProjectOutUnseen(u, d_v);
      const int row = 3 * s + c;
      FieldGradients row_grads;
      if (jacobians[0] != nullptr) {
        row_grads.triplane = jacobians[0] + size_t{1} * row * sizes[0];
      }
      if (jacobians[1] != nullptr) {
        row_grads.mlp = jacobians[1] + size_t{1} * row * sizes[1];
      }
      field_->Backward(params, d_v, row_grads, nullptr, &workspace_);
    }
  }
  return true;
}

}  // namespace es
