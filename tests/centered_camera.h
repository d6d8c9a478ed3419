#ifndef EULERSPLAT_TESTS_CENTERED_CAMERA_H_
#define EULERSPLAT_TESTS_CENTERED_CAMERA_H_

// The tests' pinhole cameras: square pixels, the principal point at the
// image centre.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/model/camera.h"

namespace es {

// width x height pixels, focal length `focal` on both axes, at the world
// origin looking down +z.
inline Camera CenteredCamera(int width, int height, double focal) {
  Camera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal;
  c.cx = width / 2.0;
  c.cy = height / 2.0;
  return c;
}

// `intrinsics` moved to `center`, looking at the world origin, world +y
// pointing down the image.
inline Camera LookingAtOrigin(Camera intrinsics,
                              const Eigen::Vector3d& center) {
  const Eigen::Vector3d z = (-center).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, 1, 0).cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.row(0) = x;
  r.row(1) = y;
  r.row(2) = z;
  intrinsics.q_cw = Eigen::Quaterniond(r);
  intrinsics.t_cw = -r * center;
  return intrinsics;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_CENTERED_CAMERA_H_
