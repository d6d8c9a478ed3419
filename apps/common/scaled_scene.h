#ifndef EULERSPLAT_APPS_COMMON_SCALED_SCENE_H_
#define EULERSPLAT_APPS_COMMON_SCALED_SCENE_H_

#include <string>

#include "core/io/scene.h"

namespace es {

// The scene in `dir` with its images scaled by `image_scale` (the apps'
// --image_scale), otherwise default scene options.
Scene LoadScaledScene(const std::string& dir, double image_scale);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_SCALED_SCENE_H_
