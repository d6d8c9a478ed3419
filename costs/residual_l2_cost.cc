#include "costs/residual_l2_cost.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/loop/cycle_time.h"
#include "core/base/stage_profile.h"
#include "costs/residual_l2_terms.h"
#include "costs/scalar_loss.h"

namespace es {

double ResidualL2Loss(const std::vector<double>& residuals, double scale,
                      double* d_residuals) {
  ScopedStage timer(Stage::kLossResidual);
  return ResidualL2Mean(residuals.data(), residuals.size(), scale,
                        d_residuals);
}

ResidualL2Cost::ResidualL2Cost(const ResidualField* field, int count,
                               const std::vector<int>* dynamic_index,
                               const std::vector<int>* start_times,
                               int cycle_length, int frame_index)
    : field_(field),
      dynamic_index_(dynamic_index),
      start_times_(start_times),
      cycle_length_(cycle_length),
      frame_index_(frame_index) {
  CHECK(field_ != nullptr);
  CHECK_EQ(dynamic_index_->size(), start_times_->size());
  set_num_residuals(1);
  *mutable_parameter_block_sizes() = {3 * count,
                                      field_->triplane().num_params(),
                                      field_->mlp().num_params()};
}

bool ResidualL2Cost::Evaluate(double const* const* parameters,
                              double* residuals, double** jacobians) const {
  const int m = static_cast<int>(dynamic_index_->size());
  const FieldParams params{parameters[1], parameters[2]};
  x0_.resize(3 * static_cast<size_t>(m));
  t_.resize(m);
  p_.resize(m);
  for (int k = 0; k < m; ++k) {
    const double* x = parameters[0] + 3 * (*dynamic_index_)[k];
    std::copy(x, x + 3, &x0_[3 * k]);
    t_[k] = CycleIndex(frame_index_, (*start_times_)[k], cycle_length_);
    p_[k] = CycleNumber(frame_index_, (*start_times_)[k], cycle_length_);
  }
  out_.resize(static_cast<size_t>(m) * kResidualDim);
  if (m > 0) {
    field_->Evaluate(params, m, x0_.data(), t_.data(), p_.data(),
                     out_.data(), &ws_);
  }
  const bool want_grad = jacobians != nullptr;
  d_out_.resize(out_.size());
  const double loss =
      ResidualL2Loss(out_, 1.0, want_grad ? d_out_.data() : nullptr);
  const double r = ScalarLossResidual(loss);
  residuals[0] = r;
  if (!want_grad) return true;
  const std::vector<int32_t>& sizes = parameter_block_sizes();
  for (int b = 0; b < 3; ++b)
    if (jacobians[b]) std::fill(jacobians[b], jacobians[b] + sizes[b], 0.0);
  if (m == 0) return true;
  d_x0_.assign(x0_.size(), 0.0);
  field_->Backward(params, d_out_.data(), {jacobians[1], jacobians[2]},
                   jacobians[0] ? d_x0_.data() : nullptr, &ws_);
  if (jacobians[0]) {
    for (int k = 0; k < m; ++k) {
      double* d = jacobians[0] + 3 * (*dynamic_index_)[k];
      for (int j = 0; j < 3; ++j) d[j] = d_x0_[3 * k + j];
    }
  }
  const double inv_r = 1.0 / r;
  for (int b = 0; b < 3; ++b) {
    if (!jacobians[b]) continue;
    for (int i = 0; i < sizes[b]; ++i) jacobians[b][i] *= inv_r;
  }
  return true;
}

}  // namespace es
