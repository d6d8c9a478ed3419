#include "core/viz/camera_path.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/base/input_error.h"

namespace es {
namespace {

Camera MakeCamera(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  Camera c;
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 50;
  c.cx = 31;  // off-center principal point on purpose
  c.cy = 25;
  c.q_cw = q;
  c.t_cw = t;
  return c;
}

Camera Intrinsics() {
  return MakeCamera(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
}

Eigen::Quaterniond Rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(CameraPathTest, ModeNamesRoundTripAndUnknownThrows) {
  for (CameraMode m : {CameraMode::kInput, CameraMode::kFixed,
                       CameraMode::kFixedTime, CameraMode::kOrbit}) {
    EXPECT_EQ(ParseCameraMode(CameraModeName(m)), m);
  }
  EXPECT_THROW(ParseCameraMode("spiral"), InputError);
}

TEST(CameraPathTest, SlerpEndpointsAreExact) {
  const Camera a = MakeCamera(Rotation(0.3, {1, 2, 3}), {0.1, -0.2, 0.3});
  const Camera b = MakeCamera(Rotation(-1.1, {0, 1, 0.2}), {2, 0.5, -1});
  const Camera s0 = InterpolateCameras(a, b, 0.0);
  const Camera s1 = InterpolateCameras(a, b, 1.0);
  EXPECT_EQ(s0.q_cw.coeffs(), a.q_cw.coeffs());
  EXPECT_EQ(s0.t_cw, a.t_cw);
  EXPECT_EQ(s1.q_cw.coeffs(), b.q_cw.coeffs());
  EXPECT_EQ(s1.t_cw, b.t_cw);
}

TEST(CameraPathTest, SlerpMidpointHalvesRotationAndCenter) {
  const Eigen::Vector3d axis(0.2, 1, -0.4);
  const Camera a = MakeCamera(Rotation(0.2, axis), {0, 0, 1});
  const Camera b = MakeCamera(Rotation(1.4, axis), {1, 2, 3});
  const Camera m = InterpolateCameras(a, b, 0.5);
  EXPECT_LT(m.q_cw.angularDistance(Rotation(0.8, axis)), 1e-12);
  EXPECT_LT((m.Center() - 0.5 * (a.Center() + b.Center())).norm(), 1e-12);
  EXPECT_NEAR(m.q_cw.norm(), 1.0, 1e-12);
}

TEST(CameraPathTest, SlerpTakesShorterArcForFlippedQuaternion) {
  const Camera a = MakeCamera(Rotation(0.1, {0, 0, 1}), {0, 0, 0});
  Camera b = MakeCamera(Rotation(0.5, {0, 0, 1}), {0, 0, 0});
  b.q_cw.coeffs() *= -1;  // same rotation, other hemisphere
  const Camera m = InterpolateCameras(a, b, 0.5);
  EXPECT_LT(m.q_cw.angularDistance(Rotation(0.3, {0, 0, 1})), 1e-12);
}

TEST(CameraPathTest, ResampleKeepsEndpointsAndIdentityCount) {
  std::vector<Camera> path;
  for (int i = 0; i < 5; ++i) {
    path.push_back(MakeCamera(Rotation(0.2 * i, {0, 1, 0}),
                              {0.5 * i, 0, 0}));
  }
  const std::vector<Camera> same = ResamplePath(path, 5);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(same[i].t_cw, path[i].t_cw);

  const std::vector<Camera> dense = ResamplePath(path, 9);
  ASSERT_EQ(dense.size(), 9u);
  EXPECT_EQ(dense.front().t_cw, path.front().t_cw);
  EXPECT_EQ(dense.back().t_cw, path.back().t_cw);
  EXPECT_EQ(dense.back().q_cw.coeffs(), path.back().q_cw.coeffs());
  // Pose 3 of 9 sits halfway between input poses 1 and 2.
  const Camera mid = InterpolateCameras(path[1], path[2], 0.5);
  EXPECT_LT((dense[3].Center() - mid.Center()).norm(), 1e-12);
  EXPECT_LT(dense[3].q_cw.angularDistance(mid.q_cw), 1e-12);
  EXPECT_EQ(ResamplePath(path, 1)[0].t_cw, path[0].t_cw);
}

TEST(CameraPathTest, LookAtCentersTargetWithImageUpAlongUp) {
  const Camera intrinsics = Intrinsics();
  const Eigen::Vector3d eye(3, -1, 2), target(0.5, 0.2, -0.3);
  const Eigen::Vector3d up(0, 0, 1);
  const Camera c = LookAt(intrinsics, eye, target, up);
  EXPECT_LT((c.Center() - eye).norm(), 1e-12);
  const Eigen::Vector3d t_cam = c.WorldToCamera(target);
  ASSERT_GT(t_cam.z(), 0);
  const Eigen::Vector2d uv = c.Project(t_cam);
  EXPECT_NEAR(uv.x(), c.cx, 1e-9);
  EXPECT_NEAR(uv.y(), c.cy, 1e-9);
  // A point above the target appears higher in the image (smaller v).
  const Eigen::Vector2d above = c.Project(c.WorldToCamera(target + up));
  EXPECT_LT(above.y(), c.cy);
  EXPECT_NEAR(above.x(), c.cx, 1e-9);  // no roll
  // Degenerate up (along the view direction) still gives a valid rotation.
  const Camera d = LookAt(intrinsics, {0, 0, 5}, {0, 0, 0}, {0, 0, 1});
  EXPECT_NEAR(d.R().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(d.Project(d.WorldToCamera({0, 0, 0})).x(), d.cx, 1e-9);
}

TEST(CameraPathTest, MeanUpDirectionOfCamerasIsMinusTheirY) {
  const Camera c = Intrinsics();
  // Identity rotation: camera y is world y, so image up is world -y.
  EXPECT_LT((MeanUpDirection({c, c}) - Eigen::Vector3d(0, -1, 0)).norm(),
            1e-12);
}

TEST(CameraPathTest, OrbitKeepsCenterCenteredAndRadius) {
  const Eigen::Vector3d center(1, 2, -0.5), up(0, -1, 0);
  const Camera start =
      LookAt(Intrinsics(), Eigen::Vector3d(1, 1, -4), center, up);
  const double radius = (start.Center() - center).norm();
  for (double degrees : {40.0, 360.0}) {
    const std::vector<Camera> orbit = OrbitPath(start, center, up, degrees, 12);
    ASSERT_EQ(orbit.size(), 12u);
    EXPECT_LT((orbit[0].Center() - start.Center()).norm(), 1e-12);
    // Offsets from the axis through the center, in the orbit's plane.
    const auto flat = [&](const Eigen::Vector3d& x) {
      const Eigen::Vector3d d = x - center;
      return Eigen::Vector3d(d - d.dot(up) * up).normalized();
    };
    double max_angle = 0;
    for (const Camera& c : orbit) {
      const Eigen::Vector2d uv = c.Project(c.WorldToCamera(center));
      EXPECT_NEAR(uv.x(), c.cx, 1e-9);
      EXPECT_NEAR(uv.y(), c.cy, 1e-9);
      EXPECT_NEAR((c.Center() - center).norm(), radius, 1e-12);
      // Height along the axis is that of the start.
      EXPECT_NEAR((c.Center() - start.Center()).dot(up), 0.0, 1e-12);
      max_angle = std::max(
          max_angle,
          std::acos(std::clamp(flat(c.Center()).dot(flat(start.Center())),
                               -1.0, 1.0)));
    }
    if (degrees < 360) {
      EXPECT_NEAR(max_angle, 20.0 * M_PI / 180, 1e-9);  // sin peaks at k=3
    } else {
      EXPECT_NEAR(max_angle, M_PI, 1e-9);  // k = 6 is opposite the start
    }
  }
}

}  // namespace
}  // namespace es
