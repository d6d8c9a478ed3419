#ifndef EULERSPLAT_SYNTH_VELOCITY_GRID_H_
#define EULERSPLAT_SYNTH_VELOCITY_GRID_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/io/velocity_grid.h"
#include "synth/flow.h"

namespace es {

// The ground truth of a synthetic scene: its flow sampled on the grid nodes.
VelocityGrid SampleVelocityGrid(const SynthFlow& flow,
                                const Eigen::AlignedBox3d& box,
                                const Eigen::Vector3i& resolution);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_VELOCITY_GRID_H_
