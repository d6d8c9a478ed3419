#ifndef EULERSPLAT_CORE_FLOW_SCENE_FLOW_IO_H_
#define EULERSPLAT_CORE_FLOW_SCENE_FLOW_IO_H_

#include <string>
#include <vector>

#include "core/flow/flow_lifting.h"

namespace es {

// Lifted scene-flow samples (Stage 2's targets), kept so Stage 3 can keep
// them as a prior on V. Binary: the magic line "eulersplat scene flow
// samples v2\n", the count (int64), then per sample x, v and unseen (9
// float64, little-endian); v1 files (x and v only, unseen zero) still load.
// Written atomically; reads throw InputError naming the file for a wrong
// magic, a count the file cannot hold, a non-finite value, or an unseen
// direction longer than a unit vector.
void SaveSceneFlowSamples(const std::vector<SceneFlowSample>& samples,
                          const std::string& path);
std::vector<SceneFlowSample> LoadSceneFlowSamples(const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_FLOW_SCENE_FLOW_IO_H_
