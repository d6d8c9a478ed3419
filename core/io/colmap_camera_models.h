#ifndef EULERSPLAT_CORE_IO_COLMAP_CAMERA_MODELS_H_
#define EULERSPLAT_CORE_IO_COLMAP_CAMERA_MODELS_H_

#include <string>

namespace es {

// COLMAP's camera models: the id stored in cameras.bin, the name used in
// cameras.txt and the number of parameters, as defined by COLMAP.
struct ColmapCameraModelInfo {
  int id;
  const char* name;
  int num_params;
};

// Returns nullptr for an unknown id or name.
const ColmapCameraModelInfo* FindColmapCameraModel(int id);
const ColmapCameraModelInfo* FindColmapCameraModel(const std::string& name);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_COLMAP_CAMERA_MODELS_H_
