#include "core/io/colmap_camera_models.h"

namespace es {
namespace {

constexpr ColmapCameraModelInfo kModels[] = {
    {0, "SIMPLE_PINHOLE", 3},
    {1, "PINHOLE", 4},
    {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},
    {4, "OPENCV", 8},
    {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},
    {7, "FOV", 5},
    {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5},
    {10, "THIN_PRISM_FISHEYE", 12},
};

}  // namespace

const ColmapCameraModelInfo* FindColmapCameraModel(int id) {
  for (const ColmapCameraModelInfo& m : kModels)
    if (m.id == id) return &m;
  return nullptr;
}

const ColmapCameraModelInfo* FindColmapCameraModel(const std::string& name) {
  for (const ColmapCameraModelInfo& m : kModels)
    if (name == m.name) return &m;
  return nullptr;
}

}  // namespace es
