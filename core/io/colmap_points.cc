#include "core/io/colmap_points.h"

#include <algorithm>
#include <string>

#include "core/base/input_error.h"

namespace es {

void SortPointsById(const std::filesystem::path& path,
                    std::vector<ColmapPoint3D>* points) {
  std::sort(points->begin(), points->end(),
            [](const ColmapPoint3D& a, const ColmapPoint3D& b) {
              return a.id < b.id;
            });
  for (size_t i = 1; i < points->size(); ++i)
    if ((*points)[i].id == (*points)[i - 1].id)
      throw InputError(path.string() + ": duplicate point id " +
                       std::to_string((*points)[i].id));
}

}  // namespace es
