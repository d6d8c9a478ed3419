#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FLOW_PRETRAIN_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FLOW_PRETRAIN_H_

// Stage 2's V pretraining (PretrainMotionField, solvers/train/
// flow_pretrain.h) on a CUDA device: the same Adam steps as the CPU's
// (flow_pretrain_steps.h: the same batches, learning-rate decay, triplane
// total variation, divergence guard and progress calls), with V's
// parameters, gradients and moments on the device; a step brings back
// only the loss and finiteness flags. The lifted samples are uploaded
// once. No CUDA types; failures throw CudaError.

#include <vector>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "solvers/train/flow_pretrain.h"

namespace es {
namespace cuda {

// PretrainMotionField's contract and report, Adam only: throws InputError
// for the lbfgs and lm solvers (they run on the CPU), and as the CPU does
// for no samples; TrainingDiverged as the CPU does. `field` (its
// parameters are the start) receives the fitted parameters.
FlowPretrainReport PretrainMotionFieldOnDevice(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, MotionField* field);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_FLOW_PRETRAIN_H_
