#include "synth/velocity_grid.h"

#include <glog/logging.h>

namespace es {

VelocityGrid SampleVelocityGrid(const SynthFlow& flow,
                                const Eigen::AlignedBox3d& box,
                                const Eigen::Vector3i& resolution) {
  CHECK(resolution.minCoeff() >= 2) << resolution.transpose();
  VelocityGrid grid;
  grid.resolution = resolution;
  grid.box = box;
  grid.values.resize(static_cast<size_t>(resolution.prod()) * 3);
  for (int k = 0; k < resolution.z(); ++k) {
    for (int j = 0; j < resolution.y(); ++j) {
      for (int i = 0; i < resolution.x(); ++i) {
        const Eigen::Vector3d v = flow.Velocity(grid.Node(i, j, k));
        const size_t index =
            ((static_cast<size_t>(k) * resolution.y() + j) * resolution.x() +
             i) * 3;
        for (int c = 0; c < 3; ++c) grid.values[index + c] = v[c];
      }
    }
  }
  return grid;
}

}  // namespace es
