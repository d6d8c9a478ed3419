#ifndef EULERSPLAT_APPS_COMMON_JOINT_FLAGS_H_
#define EULERSPLAT_APPS_COMMON_JOINT_FLAGS_H_

// es_train's flags (Stage 3: --scene, --init, --out, the trainer's knobs,
// --device). Defined here, they exist only in the binaries that call
// JointStageOptionsFromFlags.

#include "apps/common/device_flag.h"
#include "solvers/train/joint_stage.h"

namespace es {

// The Stage 3 options the flags give, and in *device where it trains.
// Throws InputError naming the flag for a value out of range, and for a
// --device that is unknown or not usable here. On cuda the loop texture
// term is off unless --loop_texture_weight is given (said on stdout).
JointStageOptions JointStageOptionsFromFlags(ComputeDevice* device);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_JOINT_FLAGS_H_
