#ifndef EULERSPLAT_CORE_MODEL_GAUSSIAN_INIT_H_
#define EULERSPLAT_CORE_MODEL_GAUSSIAN_INIT_H_

#include <Eigen/Core>
#include <vector>

#include "core/model/gaussians.h"

namespace es {

// For each point, the mean squared distance to its k nearest other points
// (exact; a uniform hash grid searched in growing shells). Points with fewer
// than k others use the ones there are; a lone point gets 0.
std::vector<double> MeanSquaredKnnDistances(
    const std::vector<Eigen::Vector3d>& points, int k = 3);

// Seeds one Gaussian per point the way 3DGS does: isotropic scale
// sqrt(mean squared distance to the 3 nearest neighbours) (floored so
// duplicate points stay finite), colour as the SH DC term, opacity 0.1,
// identity rotation, dynamic logit 0. `colors` are RGB in [0, 1].
GaussianSet InitGaussiansFromPoints(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<Eigen::Vector3d>& colors,
                                    int sh_degree);

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_GAUSSIAN_INIT_H_
