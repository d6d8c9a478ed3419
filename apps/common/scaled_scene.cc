#include "apps/common/scaled_scene.h"

namespace es {

Scene LoadScaledScene(const std::string& dir, double image_scale) {
  SceneOptions options;
  options.image_scale = image_scale;
  return LoadScene(dir, options);
}

}  // namespace es
