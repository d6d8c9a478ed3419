#ifndef EULERSPLAT_COSTS_SCENE_FLOW_COST_H_
#define EULERSPLAT_COSTS_SCENE_FLOW_COST_H_

#include <vector>

#include <ceres/cost_function.h>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"

namespace es {

// Scene-flow samples laid out as the field evaluates them.
struct SceneFlowBatch {
  std::vector<double> x;       // n x 3, world positions
  std::vector<double> target;  // n x 3, lifted velocities V'(x)
  std::vector<double> unseen;  // n x 3, SceneFlowSample::unseen (or zero)

  int size() const { return static_cast<int>(x.size() / 3); }
  // Replaces the contents with samples[indices[k]] (reusing the storage).
  void Assign(const std::vector<SceneFlowSample>& samples,
              const std::vector<int>& indices);
  void AssignAll(const std::vector<SceneFlowSample>& samples);
};

// Scene-flow pretraining loss of V over a mini-batch,
//   l = mean_s 0.5 |P_s (V(x_s) - V'(x_s))|^2,
// P_s = I - u_s u_s^T scaling the residual along the sample's unseen
// direction u_s by 1 - |u_s|^2 (a unit u_s projects it out; zero: the
// identity),
// exposed as one residual r = sqrt(2 l + eps) so that J^T r = dl/dtheta
// (see docs/DESIGN.md). Parameter blocks: the field's triplane, then its MLP.
// The batch is read at each Evaluate, so a training loop refills it in place
// between steps. Not thread-safe: Evaluate reuses one workspace.
class SceneFlowCost : public ceres::CostFunction {
 public:
  SceneFlowCost(const MotionField* field, const SceneFlowBatch* batch,
                double eps = 1e-12);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // l itself, with dl/dtheta accumulated (+=) into `grads` (blocks may be
  // null): the form Adam and LBFGS consume.
  double Loss(const FieldParams& params, const FieldGradients& grads) const;

 private:
  const MotionField* field_;
  const SceneFlowBatch* batch_;
  double eps_;
  mutable FieldWorkspace workspace_;
  mutable std::vector<double> velocity_, d_velocity_;
};

// The same fit as a true least-squares problem for Ceres' solvers: 3
// residuals per sample, P_s (V(x_s) - V'(x_s)), over the same two blocks.
// The batch size is fixed at construction. Ceres stores each residual
// block's Jacobian densely (3n x num_params), so this suits small fields or
// small batches.
class SceneFlowResiduals : public ceres::CostFunction {
 public:
  SceneFlowResiduals(const MotionField* field, const SceneFlowBatch* batch);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const MotionField* field_;
  const SceneFlowBatch* batch_;
  mutable FieldWorkspace workspace_;
};

}  // namespace es

#endif  // EULERSPLAT_COSTS_SCENE_FLOW_COST_H_
