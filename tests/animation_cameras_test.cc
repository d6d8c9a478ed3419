// The camera paths of es_animate's stage (core/viz/animation.h): which
// view --camera fixed holds by default, which anchors are refused, and the
// orbit's center.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/base/input_error.h"
#include "core/viz/animation.h"

using ::testing::HasSubstr;

namespace es {
namespace {

// Five frames whose cameras stand at x = 0..4, frame 3 held out.
Scene LineOfCameras() {
  Scene scene;
  scene.dir = "scene_dir";
  for (int i = 0; i < 5; ++i) {
    Frame f;
    f.camera.width = 16;
    f.camera.height = 12;
    f.camera.fx = f.camera.fy = 10;
    f.camera.t_cw = Eigen::Vector3d(-i, 0, 0);
    f.time_index = i;
    scene.frames.push_back(f);
  }
  scene.train = {0, 1, 2, 4};
  scene.test = {3};
  return scene;
}

// The message of the InputError `f` throws; empty when it throws none.
template <typename F>
std::string Refusal(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AnimationCamerasTest, FixedHoldsTheFirstHeldOutViewByDefault) {
  const Scene scene = LineOfCameras();
  AnimationOptions o;
  o.camera = CameraMode::kFixed;
  o.frames = 7;
  const std::vector<Camera> path = AnimationCameras(scene, LoopModel(), o);
  ASSERT_EQ(path.size(), 7u);
  for (const Camera& c : path) EXPECT_EQ(c.t_cw, scene.frames[3].camera.t_cw);
  o.anchor_frame = 1;
  EXPECT_EQ(AnimationCameras(scene, LoopModel(), o)[4].t_cw,
            scene.frames[1].camera.t_cw);
}

TEST(AnimationCamerasTest, RefusesAnchorsThatDoNotExist) {
  Scene scene = LineOfCameras();
  AnimationOptions o;
  o.camera = CameraMode::kFixed;
  o.anchor_frame = 5;
  EXPECT_THAT(Refusal([&] { AnimationCameras(scene, LoopModel(), o); }),
              HasSubstr("--anchor_frame 5"));
  // No held-out frame to default to: the scene is named.
  scene.test.clear();
  o.anchor_frame = -1;
  EXPECT_THAT(Refusal([&] { AnimationCameras(scene, LoopModel(), o); }),
              HasSubstr("scene_dir: no held-out frames"));
}

TEST(AnimationCamerasTest, InputPathKeepsTheVideosCameras) {
  const Scene scene = LineOfCameras();
  AnimationOptions o;
  o.frames = 5;
  const std::vector<Camera> path = AnimationCameras(scene, LoopModel(), o);
  ASSERT_EQ(path.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(path[i].t_cw, scene.frames[i].camera.t_cw) << i;
  }
}

TEST(AnimationCamerasTest, OrbitNeedsAModelToCircle) {
  const Scene scene = LineOfCameras();
  AnimationOptions o;
  o.camera = CameraMode::kOrbit;
  o.model_dir = "model_dir";
  EXPECT_THAT(Refusal([&] { AnimationCameras(scene, LoopModel(), o); }),
              HasSubstr("model_dir: model is empty"));
  // The orbit circles the water's median, whatever the scenery does.
  LoopModel model;
  model.gaussians.Resize(4);
  const double x[] = {0.0, 1.0, 2.0, 100.0};  // Gaussian 3: scenery
  for (int i = 0; i < 4; ++i) model.gaussians.means[3 * i] = x[i];
  model.gaussians.means[2] = model.gaussians.means[5] = 3;  // z
  model.gaussians.means[8] = 3;
  model.dynamic_index = {0, 1, 2};
  o.frames = 4;
  o.orbit_degrees = 360;
  const std::vector<Camera> path = AnimationCameras(scene, model, o);
  ASSERT_EQ(path.size(), 4u);
  const Eigen::Vector3d center(1, 0, 3);
  // Every camera looks at the center: it projects to the principal point.
  for (const Camera& c : path) {
    const Eigen::Vector3d p = c.q_cw * center + c.t_cw;
    EXPECT_NEAR(p.x() / p.z(), 0.0, 1e-9);
    EXPECT_NEAR(p.y() / p.z(), 0.0, 1e-9);
  }
}

}  // namespace
}  // namespace es
