#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_STAGE_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_STAGE_H_

// Stage 2 (es_flowinit): the motion field V initialized from optical flow
// lifted to 3D with the static model's depth, and pretrained on those
// samples.

#include <vector>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "solvers/train/flow_init_options.h"
#include "solvers/train/flow_pretrain.h"
#include "solvers/train/training_history.h"

namespace es {

// Lifts the optical flow of the scene's water to 3D samples (printing a
// line per frame pair and the rejection counts), keeps a random subset of
// at most max_samples and, with an oracle, gives them the true velocity.
// Throws InputError when no sample survives the checks.
SceneFlowResult LiftWaterFlow(const Scene& scene, const GaussianSet& model,
                              const FlowInitStageOptions& options);

// Fits `field` (set to span the dynamic Gaussians' box) to the samples
// with `pretrain`: a progress line (with ETA) and a `history` row per log.
FlowPretrainReport PretrainFieldOnSamples(
    const FlowPretrainer& pretrain, const SceneFlowResult& lifted,
    const GaussianSet& model, const std::vector<int>& dynamic,
    const FlowPretrainOptions& options, TrainingHistory* history,
    MotionField* field);

// Stage 2: checks the inputs, loads the scene and Stage 1's model, lifts
// the water's flow, pretrains V on it with `pretrain` (PretrainMotionField
// or its device twin) and writes out_dir/motion_field.bin,
// scene_flow_samples.bin, flow_history.csv and flow_metrics.json (with
// the ground-truth errors when the scene has gt/). Throws InputError, and
// writes nothing, when an oracle is asked of a scene without gt/, the
// model has no dynamic Gaussian or no sample survives.
FlowInitStageResult RunFlowInitStage(
    const FlowInitStageOptions& options,
    const FlowPretrainer& pretrain = PretrainMotionField);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_STAGE_H_
