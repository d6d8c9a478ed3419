#ifndef EULERSPLAT_CORE_IO_COLMAP_POINTS_H_
#define EULERSPLAT_CORE_IO_COLMAP_POINTS_H_

#include <filesystem>
#include <vector>

#include "core/io/colmap_io.h"

namespace es {

// Sorts the points read from `path` by id; throws InputError naming the
// file when two share an id.
void SortPointsById(const std::filesystem::path& path,
                    std::vector<ColmapPoint3D>* points);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_COLMAP_POINTS_H_
