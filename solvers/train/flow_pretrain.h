#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_H_

#include <vector>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "solvers/train/flow_pretrain_options.h"

namespace es {

// RMSE of V against the samples (evaluated in chunks).
double FitRmse(const MotionField& field,
               const std::vector<SceneFlowSample>& samples);

// Fits field (its current parameters are the start) to the samples with
// the chosen solver. Throws InputError when there are no samples, or LM is
// asked for a field too large for its dense Jacobian.
FlowPretrainReport PretrainMotionField(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, MotionField* field);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_H_
