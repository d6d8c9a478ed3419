#include "core/io/colmap_io.h"

#include <filesystem>

namespace es {

bool HasColmapBinary(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  return fs::exists(d / "cameras.bin") && fs::exists(d / "images.bin") &&
         fs::exists(d / "points3D.bin");
}

ColmapModel ReadColmapModel(const std::string& dir) {
  return HasColmapBinary(dir) ? ReadColmapBinary(dir) : ReadColmapText(dir);
}

}  // namespace es
