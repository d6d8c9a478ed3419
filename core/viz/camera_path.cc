#include "core/viz/camera_path.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <glog/logging.h>

#include "core/base/input_error.h"

namespace es {

std::string CameraModeName(CameraMode mode) {
  switch (mode) {
    case CameraMode::kInput: return "input";
    case CameraMode::kFixed: return "fixed";
    case CameraMode::kFixedTime: return "fixed_time";
    case CameraMode::kOrbit: return "orbit";
  }
  LOG(FATAL) << "unknown camera mode";
  return "";
}

CameraMode ParseCameraMode(const std::string& name) {
  for (CameraMode mode : {CameraMode::kInput, CameraMode::kFixed,
                          CameraMode::kFixedTime, CameraMode::kOrbit}) {
    if (CameraModeName(mode) == name) return mode;
  }
  throw InputError("--camera: unknown mode '" + name +
                   "' (input, fixed, fixed_time or orbit)");
}

Camera InterpolateCameras(const Camera& a, const Camera& b, double s) {
  if (s == 0.0) return a;
  if (s == 1.0) {
    Camera out = a;
    out.q_cw = b.q_cw;
    out.t_cw = b.t_cw;
    return out;
  }
  const Eigen::Quaterniond qa = a.q_cw.normalized();
  const Eigen::Quaterniond qb = b.q_cw.normalized();
  const Eigen::Vector3d center = (1 - s) * a.Center() + s * b.Center();
  Camera out = a;
  out.q_cw = qa.slerp(s, qb);  // Eigen takes the shorter arc
  out.t_cw = -(out.R() * center);
  return out;
}

std::vector<Camera> ResamplePath(const std::vector<Camera>& path,
                                 int count) {
  CHECK(!path.empty());
  CHECK_GT(count, 0);
  const int n = static_cast<int>(path.size());
  if (count == n) return path;
  std::vector<Camera> out;
  out.reserve(count);
  for (int k = 0; k < count; ++k) {
    if (n == 1 || count == 1) {
      out.push_back(path[0]);
      continue;
    }
    const double u = static_cast<double>(k) * (n - 1) / (count - 1);
    const int i = std::min(static_cast<int>(std::floor(u)), n - 2);
    out.push_back(InterpolateCameras(path[i], path[i + 1], u - i));
  }
  return out;
}

Camera LookAt(const Camera& intrinsics, const Eigen::Vector3d& eye,
              const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - eye).normalized();
  // Image y points down, so it is minus the part of `up` orthogonal to z.
  Eigen::Vector3d y = -(up - up.dot(z) * z);
  if (y.norm() < 1e-9 * up.norm() || y.norm() == 0.0) {
    y = z.unitOrthogonal();  // up along the view direction: any roll
  }
  y.normalize();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d r_cw;
  r_cw.row(0) = x.transpose();
  r_cw.row(1) = y.transpose();
  r_cw.row(2) = z.transpose();
  Camera out = intrinsics;
  out.q_cw = Eigen::Quaterniond(r_cw);
  out.t_cw = -(r_cw * eye);
  return out;
}

Eigen::Vector3d MeanUpDirection(const std::vector<Camera>& cameras) {
  CHECK(!cameras.empty());
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const Camera& c : cameras) up -= c.R().row(1).transpose();
  CHECK_GT(up.norm(), 0.0) << "cameras' up directions cancel out";
  return up.normalized();
}

std::vector<Camera> OrbitPath(const Camera& start,
                              const Eigen::Vector3d& center,
                              const Eigen::Vector3d& up, double degrees,
                              int count) {
  CHECK_GT(count, 0);
  const Eigen::Vector3d axis = up.normalized();
  const Eigen::Vector3d offset = start.Center() - center;
  std::vector<Camera> out;
  out.reserve(count);
  for (int k = 0; k < count; ++k) {
    const double phase = 2.0 * M_PI * k / count;
    const double angle = degrees >= 360.0
                             ? phase
                             : 0.5 * degrees * M_PI / 180.0 * std::sin(phase);
    const Eigen::Vector3d eye =
        center + Eigen::AngleAxisd(angle, axis) * offset;
    out.push_back(LookAt(start, eye, center, axis));
  }
  return out;
}

}  // namespace es
