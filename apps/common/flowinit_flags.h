#ifndef EULERSPLAT_APPS_COMMON_FLOWINIT_FLAGS_H_
#define EULERSPLAT_APPS_COMMON_FLOWINIT_FLAGS_H_

// es_flowinit's flags and what they ask of Stage 2
// (solvers/train/flow_init_stage.h). Defined here, they exist in the
// binary that calls these functions only; es_flowinit reads them through
// these alone, so that no other flags file is linked in for a flag of the
// same name.

#include "apps/common/device_flag.h"
#include "core/base/communicator.h"
#include "solvers/train/flow_init_options.h"
#include "solvers/train/flow_pretrain_options.h"

namespace es {

// Checks every flag's value (before any work); throws InputError naming it.
void CheckFlowInitFlags();
// --device's pretraining, checked before the optical flow is computed: the
// CUDA device fits V with --solver adam only, and several ranks (`comm`)
// or --batch_shards need the CPU and adam, a shard per rank at least
// (InputError otherwise).
FlowPretrainer FlowPretrainerFromFlags(const Communicator& comm);
// The stage's options; throws InputError for a value no parser knows.
FlowInitStageOptions FlowInitStageOptionsFromFlags();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_FLOWINIT_FLAGS_H_
