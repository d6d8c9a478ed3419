#ifndef EULERSPLAT_COSTS_RESIDUAL_L2_COST_H_
#define EULERSPLAT_COSTS_RESIDUAL_L2_COST_H_

#include <vector>

#include <ceres/cost_function.h>

#include "core/fields/residual_field.h"

namespace es {

// Mean over the dynamic Gaussians and the kResidualDim outputs of D's
// squared outputs (residuals: num_dynamic x kResidualDim rows); 0 when
// empty. If d_residuals is not null it receives scale * dl/d residuals.
double ResidualL2Loss(const std::vector<double>& residuals, double scale,
                      double* d_residuals);

// The residual L2 regularizer on its own: D evaluated for the dynamic
// Gaussians at frame i (canonical position, cycle index and number from
// their start times), l = ResidualL2Loss, as one residual sqrt(2 l + eps).
// Blocks: the canonical means (3 count), D's triplane, D's MLP. The joint
// training loop sums this term inside JointRenderCost instead, which shares
// D's evaluation with the render. Not thread-safe.
class ResidualL2Cost : public ceres::CostFunction {
 public:
  // field, dynamic_index and start_times must outlive the cost.
  ResidualL2Cost(const ResidualField* field, int count,
                 const std::vector<int>* dynamic_index,
                 const std::vector<int>* start_times, int cycle_length,
                 int frame_index);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const ResidualField* field_;
  const std::vector<int>* dynamic_index_;
  const std::vector<int>* start_times_;
  int cycle_length_;
  int frame_index_;
  mutable FieldWorkspace ws_;
  mutable std::vector<double> x0_, out_, d_out_, d_x0_;
  mutable std::vector<int> t_, p_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_RESIDUAL_L2_COST_H_
