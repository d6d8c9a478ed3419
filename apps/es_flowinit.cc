// Stage 2: initializes the motion field V from optical flow lifted to 3D
// with the static model's depth, and pretrains it on those samples. The
// flags are in apps/common/flowinit_flags.cc, the stage in
// solvers/train/flow_init_stage.h.

#include "apps/common/flowinit_flags.h"
#include "apps/common/world.h"
#include "solvers/train/flow_init_stage.h"

constexpr char kUsage[] =
    "Stage 2: motion-field initialization from optical flow.\n"
    "  es_flowinit --scene DIR [--static DIR/static.ply] [--out DIR]\n"
    "              [--flow dis|farneback|...] [--solver adam|lbfgs|lm]\n"
    "              [--device cpu|cuda] [--batch_shards S]\n"
    "Lifts the optical flow of training frames --frame_gap apart (by "
    "default of each frame minus the static model's render of it) to 3D "
    "with the static model's depth, keeps water pixels (masks/ or the "
    "model's dynamic channel), pretrains V on them and writes <out>/"
    "motion_field.bin, scene_flow_samples.bin (the samples; es_train "
    "--flow_prior_weight keeps them as a prior), flow_history.csv and "
    "flow_metrics.json (epe_gt, rel_epe_gt when the scene has gt/). "
    "Exits 1 and writes nothing when the model has no dynamic Gaussians "
    "or no sample survives.";

int main(int argc, char** argv) {
  return es::RunAppOnRanks(argc, argv, kUsage, [](es::Communicator* comm) {
    es::CheckFlowInitFlags();
    const es::FlowPretrainer pretrain = es::FlowPretrainerFromFlags(*comm);
    es::FlowInitStageOptions o = es::FlowInitStageOptionsFromFlags();
    o.pretrain.comm = comm;
    es::RunFlowInitStage(o, pretrain);
    return 0;
  });
}
