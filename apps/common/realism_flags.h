#ifndef EULERSPLAT_APPS_COMMON_REALISM_FLAGS_H_
#define EULERSPLAT_APPS_COMMON_REALISM_FLAGS_H_

// --realism_patches, --realism_water_margin and --realism_seed: how the
// realism figures sample the videos. es_eval (a model against the input)
// and es_compare (another video against it) share them, so that their
// figures are measured alike. Defined here, they exist in the binaries that
// call RealismOptionsFromFlags only.

#include "core/metrics/realism.h"

namespace es {

// The realism options the flags give. Throws InputError for a value out of
// range, naming the flag.
RealismOptions RealismOptionsFromFlags();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_REALISM_FLAGS_H_
