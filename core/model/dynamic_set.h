#ifndef EULERSPLAT_CORE_MODEL_DYNAMIC_SET_H_
#define EULERSPLAT_CORE_MODEL_DYNAMIC_SET_H_

#include <vector>

#include <Eigen/Core>

#include "core/model/gaussians.h"

namespace es {

// The water (dynamic) Gaussians of a model and the box the fields V and D
// span around them.

// The Gaussians whose sigmoid(dynamic_logit) exceeds threshold, ascending.
std::vector<int> DynamicSet(const GaussianSet& g, double threshold);
// The same from the dynamic logits alone.
std::vector<int> DynamicSet(const std::vector<double>& dynamic_logits,
                            double threshold);

// The box the fields span: the bounds of the given Gaussians' means (all of
// them when the list is empty) padded by 10% of their size on every side
// (and at least a small absolute margin, so the box is never empty).
void FieldBox(const GaussianSet& g, const std::vector<int>& indices,
              Eigen::Vector3d* lo, Eigen::Vector3d* hi);

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_DYNAMIC_SET_H_
