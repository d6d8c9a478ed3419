#ifndef EULERSPLAT_CORE_MODEL_CAMERA_H_
#define EULERSPLAT_CORE_MODEL_CAMERA_H_

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace es {

// A pinhole camera in COLMAP conventions: x right, y down, z forward; the
// pose maps world to camera, X_cam = R(q_cw) X_world + t_cw; pixel (j, i)
// has its center at (j + 0.5, i + 0.5), so a point projects to
// u = fx * x / z + cx in the same continuous pixel coordinates COLMAP uses.
struct Camera {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Quaterniond q_cw = Eigen::Quaterniond::Identity();
  Eigen::Vector3d t_cw = Eigen::Vector3d::Zero();
  std::string image_name;  // file name relative to the scene's images/
  int image_id = -1;

  Eigen::Matrix3d R() const { return q_cw.normalized().toRotationMatrix(); }
  // Camera center in world coordinates.
  Eigen::Vector3d Center() const { return -(R().transpose() * t_cw); }
  Eigen::Vector3d WorldToCamera(const Eigen::Vector3d& x) const {
    return R() * x + t_cw;
  }
  // Pixel coordinates (continuous) of a camera-space point with z > 0.
  Eigen::Vector2d Project(const Eigen::Vector3d& x_cam) const {
    return {fx * x_cam.x() / x_cam.z() + cx, fy * x_cam.y() / x_cam.z() + cy};
  }
  // Camera-space point at depth z along the ray through pixel coords (u, v).
  Eigen::Vector3d Unproject(double u, double v, double z) const {
    return {(u - cx) / fx * z, (v - cy) / fy * z, z};
  }
  // Same camera with the image resized by `factor` (intrinsics scaled).
  Camera Scaled(double factor) const;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_CAMERA_H_
