#ifndef EULERSPLAT_CORE_VIZ_CAMERA_PATH_H_
#define EULERSPLAT_CORE_VIZ_CAMERA_PATH_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"

namespace es {

// How an animation's camera moves (es_animate --camera).
enum class CameraMode {
  kInput,      // along the input video's trajectory, time running
  kFixed,      // one held-out anchor view, time running
  kFixedTime,  // time frozen, camera along the input trajectory
  kOrbit,      // around the scene center, time running
};

// Flag spellings input, fixed, fixed_time, orbit; Parse throws InputError
// on others.
std::string CameraModeName(CameraMode mode);
CameraMode ParseCameraMode(const std::string& name);

// Pose between a (s = 0) and b (s = 1): rotation by slerp, camera center
// linearly; intrinsics, size and name from a. At s = 0 and s = 1 the pose
// is a's and b's exactly (bit for bit).
Camera InterpolateCameras(const Camera& a, const Camera& b, double s);

// `count` poses evenly spaced over a trajectory by frame index: pose k sits
// at u = k (n - 1) / (count - 1) and interpolates path[floor u] and the next.
// The first and last poses are the path's own; count == n returns the path.
std::vector<Camera> ResamplePath(const std::vector<Camera>& path, int count);

// A camera with `intrinsics`' size and focal lengths at `eye`, looking at
// `target` (which projects to the principal point), with image up along
// `up` as far as it is orthogonal to the view direction.
Camera LookAt(const Camera& intrinsics, const Eigen::Vector3d& eye,
              const Eigen::Vector3d& target, const Eigen::Vector3d& up);

// The world direction the cameras see as image up (the mean of their -y
// axes), normalized.
Eigen::Vector3d MeanUpDirection(const std::vector<Camera>& cameras);

// `count` cameras orbiting `center` about the axis `up` through it, starting
// at `start`'s position and always looking at center. degrees >= 360 goes
// once around; a smaller arc swings back and forth by +-degrees / 2 along a
// sine so the path itself loops. Radius and height stay those of `start`.
std::vector<Camera> OrbitPath(const Camera& start,
                              const Eigen::Vector3d& center,
                              const Eigen::Vector3d& up, double degrees,
                              int count);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_CAMERA_PATH_H_
