#ifndef EULERSPLAT_APPS_COMMON_DRIVER_FLAGS_H_
#define EULERSPLAT_APPS_COMMON_DRIVER_FLAGS_H_

// The all-in-one driver's flags (--scene, --video, --out, --preset, the
// iteration overrides, --device, ...). Defined here, they exist in the
// binary that calls DriverOptionsFromFlags only: eulersplat.

#include "apps/common/driver_batch.h"
#include "solvers/pipeline/pipeline_options.h"

namespace es {

// The pipeline's options the flags give, checked before any work: throws
// InputError naming the flag for a value out of range, and for --device
// cuda where no GPU can be used. Prints which stages run on the GPU when
// --device is not cpu.
PipelineOptions DriverOptionsFromFlags();

// Whether --scenes asks for a batch of scenes.
bool SceneBatchAsked();
// The batch --scenes, --groups, --ranks and --out ask for, checked before
// any work (InputError naming the flag); the other flags the user set are
// passed on to every scene's run.
SceneBatchOptions SceneBatchOptionsFromFlags();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_DRIVER_FLAGS_H_
