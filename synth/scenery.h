#ifndef EULERSPLAT_SYNTH_SCENERY_H_
#define EULERSPLAT_SYNTH_SCENERY_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/model/gaussians.h"

namespace es {

// Surface coloring: two base colors mixed by large-scale noise, modulated by
// finer noise, dark crack lines and per-Gaussian speckle, so every view has
// the multi-scale texture structure-from-motion needs.
struct SceneryMaterial {
  Eigen::Vector3d color_a{0.45, 0.42, 0.38};
  Eigen::Vector3d color_b{0.30, 0.28, 0.25};
  double frequency = 1.5;  // large-scale noise cycles per world unit
  double speckle = 0.12;   // relative per-Gaussian brightness noise
  // > 0: vertical boards this wide (world units, along x), each its own
  // shade, with dark seams between: fine, high-contrast texture that a
  // short static fit renders badly (boards a few pixels wide).
  double board_width = 0.0;
};

// The rectangle origin + s u + t v (s, t in [0, 1]), displaced along its
// normal u x v (the lit, visible side) by smooth noise of amplitude `bump`.
struct SceneryPlane {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v = Eigen::Vector3d::UnitZ();
  double bump = 0.05;
  SceneryMaterial material;
};

// An ellipsoid whose radius is perturbed by noise (relative `roughness`).
struct SceneryRock {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d radii = Eigen::Vector3d::Ones();
  double roughness = 0.25;
  SceneryMaterial material;
};

struct SceneryLayout {
  std::vector<SceneryPlane> planes;
  std::vector<SceneryRock> rocks;
  double spacing = 0.05;  // distance between neighbouring Gaussians
  Eigen::Vector3d light_direction{0.3, 1.0, 0.5};  // baked Lambert shading
};

// Covers every surface with flat, nearly opaque Gaussian discs about
// `spacing` apart, oriented along the surface. Static: dynamic logit low.
GaussianSet BuildScenery(const SceneryLayout& layout, uint64_t seed);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_SCENERY_H_
