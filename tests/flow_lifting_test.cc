#include "core/flow/flow_lifting.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"
#include "core/render/render_maps.h"
#include "synth/random_texture.h"
#include "tests/centered_camera.h"

namespace es {
namespace {

// A plane n . X = offset (world), textured by its world x and y.
struct Plane {
  Eigen::Vector3d normal;
  double offset;

  // World point on the ray through pixel index (x, y) of `camera`.
  Eigen::Vector3d Intersect(const Camera& camera, double x, double y) const {
    const Eigen::Vector3d center = camera.Center();
    const Eigen::Vector3d dir =
        camera.R().transpose() * camera.Unproject(x + 0.5, y + 0.5, 1.0);
    const double s = (offset - normal.dot(center)) / normal.dot(dir);
    return center + s * dir;
  }
  Plane Moved(const Eigen::Vector3d& t) const {
    return {normal, offset + normal.dot(t)};
  }
};

cv::Mat PlaneDepth(const Camera& camera, const Plane& plane) {
  cv::Mat depth(camera.height, camera.width, CV_32FC1);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      depth.at<float>(y, x) =
          camera.WorldToCamera(plane.Intersect(camera, x, y)).z();
    }
  }
  return depth;
}

// Exact flow of pixels of `from` seeing plane `p_from` to `to`, where the
// plane's points have moved by `t`.
cv::Mat PlaneFlow(const Camera& from, const Plane& p_from, const Camera& to,
                  const Eigen::Vector3d& t) {
  cv::Mat flow(from.height, from.width, CV_32FC2);
  for (int y = 0; y < from.height; ++y) {
    for (int x = 0; x < from.width; ++x) {
      const Eigen::Vector3d moved = p_from.Intersect(from, x, y) + t;
      const Eigen::Vector2d uv = to.Project(to.WorldToCamera(moved));
      flow.at<cv::Vec2f>(y, x) = cv::Vec2f(uv.x() - 0.5 - x, uv.y() - 0.5 - y);
    }
  }
  return flow;
}

// Renders the plane with a texture looked up by the world (x, y) of each
// pixel's surface point, shifted back by the plane's motion `t` so the
// texture moves with the plane.
cv::Mat RenderPlane(const Camera& camera, const Plane& plane,
                    const Eigen::Vector3d& t, const cv::Mat& texture,
                    double texels_per_unit) {
  cv::Mat map(camera.height, camera.width, CV_32FC2);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d p = plane.Intersect(camera, x, y) - t;
      map.at<cv::Vec2f>(y, x) =
          cv::Vec2f(texture.cols / 2.0 + p.x() * texels_per_unit,
                    texture.rows / 2.0 + p.y() * texels_per_unit);
    }
  }
  cv::Mat image;
  cv::remap(texture, image, map, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REFLECT);
  return image;
}

struct TwoViews {
  Camera a, b;
  Plane plane;
  Eigen::Vector3d motion;
};

TwoViews MakeTwoViews(int width, int height, double focal) {
  TwoViews v;
  v.a = CenteredCamera(width, height, focal);
  v.b = v.a;
  v.b.q_cw = Eigen::AngleAxisd(0.04, Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd(-0.02, Eigen::Vector3d::UnitX());
  v.b.t_cw = Eigen::Vector3d(-0.12, 0.03, 0.05);
  v.plane = {Eigen::Vector3d(0.1, -0.25, 1.0).normalized(), 4.0};
  v.motion = Eigen::Vector3d(0.15, -0.08, 0.1);
  return v;
}

cv::Mat Ones(const Camera& c) {
  return cv::Mat(c.height, c.width, CV_32FC1, cv::Scalar(1));
}

// What LiftFlow makes of one pair: its samples and its counts.
struct Lifted {
  std::vector<SceneFlowSample> samples;
  LiftingStats stats;
};

Lifted Lift(const LiftingView& first, const LiftingView& second,
            const FlowPair& flow, const LiftingOptions& options) {
  Lifted out;
  LiftFlow(first, second, flow, options, &out.samples, &out.stats);
  return out;
}

TEST(FlowLiftingTest, ExactFlowRecoversPlaneTranslation) {
  const TwoViews v = MakeTwoViews(64, 48, 60);
  const Plane moved = v.plane.Moved(v.motion);
  FlowPair flow;
  flow.forward = PlaneFlow(v.a, v.plane, v.b, v.motion);
  flow.backward = PlaneFlow(v.b, moved, v.a, -v.motion);
  const LiftingView first{&v.a, PlaneDepth(v.a, v.plane), Ones(v.a)};
  const LiftingView second{&v.b, PlaneDepth(v.b, moved), Ones(v.b)};
  LiftingOptions options;
  options.stride = 1;
  options.second_end = SecondEnd::kRenderedDepth;
  const auto [samples, stats] = Lift(first, second, flow, options);

  EXPECT_EQ(stats.candidates, 64 * 48);
  EXPECT_EQ(stats.inconsistent + stats.depth_edge + stats.no_depth +
                stats.not_water, 0);
  EXPECT_GT(stats.accepted, 64 * 48 * 3 / 4);  // some leave the image
  ASSERT_EQ(static_cast<long>(samples.size()), stats.accepted);
  for (const SceneFlowSample& s : samples) {
    // x lies on the plane and moves with it; bilinear depth on a tilted
    // plane is the only approximation.
    EXPECT_NEAR(v.plane.normal.dot(s.x), v.plane.offset, 1e-6);
    EXPECT_LT((s.v - v.motion).norm(), 1e-3 * v.motion.norm());
    EXPECT_TRUE(s.unseen.isZero());  // the rendered depth sees it all
  }
}

// Frames three video frames apart: the plane moved three times its
// per-frame motion between them, and the samples are motion per frame.
TEST(FlowLiftingTest, FrameGapDividesTheDisplacement) {
  const TwoViews v = MakeTwoViews(64, 48, 60);
  const Eigen::Vector3d displacement = 3.0 * v.motion;
  const Plane moved = v.plane.Moved(displacement);
  FlowPair flow;
  flow.forward = PlaneFlow(v.a, v.plane, v.b, displacement);
  flow.backward = PlaneFlow(v.b, moved, v.a, -displacement);
  const LiftingView first{&v.a, PlaneDepth(v.a, v.plane), Ones(v.a)};
  const LiftingView second{&v.b, PlaneDepth(v.b, moved), Ones(v.b)};
  LiftingOptions options;
  options.stride = 2;
  options.second_end = SecondEnd::kRenderedDepth;
  options.frame_gap = 3;
  const auto [samples, stats] = Lift(first, second, flow, options);
  ASSERT_GT(stats.accepted, stats.candidates / 2);
  for (const SceneFlowSample& s : samples)
    EXPECT_LT((s.v - v.motion).norm(), 1e-3 * v.motion.norm());
}

TEST(FlowLiftingTest, EstimatedFlowRecoversPlaneTranslation) {
  const TwoViews v = MakeTwoViews(160, 120, 150);
  const Plane moved = v.plane.Moved(v.motion);
  const cv::Mat texture = TwoScaleTexture(512, 512, 1, 11);
  const cv::Mat image_a = RenderPlane(v.a, v.plane, Eigen::Vector3d::Zero(),
                                      texture, 120.0);
  const cv::Mat image_b = RenderPlane(v.b, moved, v.motion, texture, 120.0);
  OpticalFlow estimator(FlowMethod::kDisMedium);
  const FlowPair flow = estimator.ComputePair(image_a, image_b);
  const LiftingView first{&v.a, PlaneDepth(v.a, v.plane), Ones(v.a)};
  const LiftingView second{&v.b, PlaneDepth(v.b, moved), Ones(v.b)};
  LiftingOptions options;
  options.second_end = SecondEnd::kRenderedDepth;
  const auto [samples, stats] = Lift(first, second, flow, options);

  ASSERT_GT(stats.accepted, stats.candidates / 2);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<double> errors;
  for (const SceneFlowSample& s : samples) {
    mean += s.v;
    errors.push_back((s.v - v.motion).norm());
  }
  mean /= samples.size();
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2,
                   errors.end());
  EXPECT_LT((mean - v.motion).norm(), 0.05 * v.motion.norm());
  EXPECT_LT(errors[errors.size() / 2], 0.15 * v.motion.norm());
}

// Each point of the plane moves by the part of v.motion across camera a's
// line of sight, which is all 2D flow observes: the facing-plane lift must
// recover exactly that, without reading the second frame's depth.
TEST(FlowLiftingTest, FacingPlaneRecoversMotionAcrossTheLineOfSight) {
  const TwoViews v = MakeTwoViews(64, 48, 60);
  const Eigen::Vector3d center = v.a.Center();
  auto across = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    const Eigen::Vector3d ray = (x - center).normalized();
    return v.motion - v.motion.dot(ray) * ray;
  };
  FlowPair flow;
  flow.forward.create(48, 64, CV_32FC2);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector3d p = v.plane.Intersect(v.a, x, y);
      const Eigen::Vector2d uv = v.b.Project(v.b.WorldToCamera(p + across(p)));
      flow.forward.at<cv::Vec2f>(y, x) =
          cv::Vec2f(uv.x() - 0.5 - x, uv.y() - 0.5 - y);
    }
  }
  flow.backward = -flow.forward;  // only read by the round-trip check
  const cv::Mat no_depth(48, 64, CV_32FC1, cv::Scalar(0));
  const LiftingView first{&v.a, PlaneDepth(v.a, v.plane), Ones(v.a)};
  const LiftingView second{&v.b, no_depth, Ones(v.b)};
  LiftingOptions options;
  options.stride = 1;
  options.max_fb_error_px = 1e9;
  ASSERT_EQ(options.second_end, SecondEnd::kFacingPlane);  // the default
  auto [samples, stats] = Lift(first, second, flow, options);

  EXPECT_EQ(stats.no_depth + stats.depth_edge, 0);
  EXPECT_GT(stats.accepted, 64 * 48 * 3 / 4);
  for (const SceneFlowSample& s : samples) {
    EXPECT_NEAR(v.plane.normal.dot(s.x), v.plane.offset, 1e-6);
    EXPECT_NEAR(s.v.dot((s.x - center).normalized()), 0.0, 1e-9);
    EXPECT_LT((s.v - across(s.x)).norm(), 1e-4 * v.motion.norm());
    // The line of sight it says nothing about, for the losses to leave free.
    EXPECT_LT((s.unseen - (s.x - center).normalized()).norm(), 1e-12);
  }
  // A partial weight on it: the same line, shortened to sqrt(1 - weight).
  options.line_of_sight_weight = 0.36;
  samples = Lift(first, second, flow, options).samples;
  ASSERT_FALSE(samples.empty());
  for (const SceneFlowSample& s : samples) {
    EXPECT_LT((s.unseen - 0.8 * (s.x - center).normalized()).norm(), 1e-12);
  }
  options.line_of_sight_weight = 1.0;  // --free_line_of_sight=false
  samples = Lift(first, second, flow, options).samples;
  ASSERT_FALSE(samples.empty());
  for (const SceneFlowSample& s : samples) EXPECT_TRUE(s.unseen.isZero());
}

// A static camera looking at a background wall (depth 4) with a foreground
// square (depth 2) whose border pixels hold a blended depth (3), as a splat
// renderer produces at an occluding edge.
struct OcclusionScene {
  Camera camera = CenteredCamera(32, 24, 30);
  cv::Mat depth;
  OcclusionScene() : depth(24, 32, CV_32FC1, cv::Scalar(4)) {
    depth(cv::Rect(10, 8, 12, 8)) = 2.0f;
    cv::rectangle(depth, cv::Rect(10, 8, 12, 8), cv::Scalar(3));
  }
};

FlowPair ConstantFlow(cv::Size size, float dx, float dy) {
  return {cv::Mat(size, CV_32FC2, cv::Scalar(dx, dy)),
          cv::Mat(size, CV_32FC2, cv::Scalar(-dx, -dy))};
}

TEST(FlowLiftingTest, RejectsDepthDiscontinuities) {
  const OcclusionScene scene;
  const LiftingView view{&scene.camera, scene.depth, Ones(scene.camera)};
  LiftingOptions options;
  options.stride = 1;
  const auto [samples, stats] =
      Lift(view, view, ConstantFlow(scene.depth.size(), 0, 0), options);
  // Every pixel whose 3x3 neighbourhood touches the blended ring is dropped:
  // the 14x10 block around the 12x8 ring, less the 8x4 pixels inside that
  // see only the square.
  EXPECT_EQ(stats.depth_edge, 14 * 10 - 8 * 4);
  EXPECT_EQ(stats.accepted, 32 * 24 - stats.depth_edge);
  for (const SceneFlowSample& s : samples) {
    const double z = scene.camera.WorldToCamera(s.x).z();
    EXPECT_TRUE(std::abs(z - 2) < 1e-6 || std::abs(z - 4) < 1e-6) << z;
    EXPECT_EQ(s.v.norm(), 0.0);
  }
}

TEST(FlowLiftingTest, RejectsInconsistentFlowAtOcclusions) {
  const Camera camera = CenteredCamera(32, 24, 30);
  const cv::Mat depth(24, 32, CV_32FC1, cv::Scalar(4));
  const LiftingView view{&camera, depth, Ones(camera)};
  FlowPair flow = ConstantFlow(depth.size(), 2, 0);
  // In frame 2 an occluder covers columns 14..17: its backward flow is zero,
  // so pixels of frame 1 landing there fail the round trip.
  flow.backward.colRange(14, 18) = cv::Scalar(0, 0);
  LiftingOptions options;
  options.stride = 1;
  options.second_end = SecondEnd::kRenderedDepth;  // x' on the wall too
  const auto [samples, stats] = Lift(view, view, flow, options);
  // Integer targets x + 2 read one column of the backward flow: columns
  // 12..15 land on the occluder.
  EXPECT_EQ(stats.inconsistent, 4 * 24);
  EXPECT_EQ(stats.outside, 2 * 24);  // columns 30, 31 land beyond 31
  EXPECT_EQ(stats.accepted, (32 - 6) * 24);
  const Eigen::Vector3d step(2 * 4 / 30.0, 0, 0);  // 2 px at depth 4, f = 30
  for (const SceneFlowSample& s : samples) {
    EXPECT_LT((s.v - step).norm(), 1e-5);
  }
}

TEST(FlowLiftingTest, RejectsFlowLeavingTheWater) {
  const Camera camera = CenteredCamera(32, 24, 30);
  const cv::Mat depth(24, 32, CV_32FC1, cv::Scalar(4));
  cv::Mat water_a = Ones(camera), water_b = Ones(camera);
  water_a.colRange(0, 4) = 0.0f;   // not candidates
  water_b.colRange(20, 32) = 0.0f;  // columns 19.. of frame 1 land here
  const LiftingView first{&camera, depth, water_a};
  const LiftingView second{&camera, depth, water_b};
  LiftingOptions options;
  options.stride = 2;
  const auto [samples, stats] =
      Lift(first, second, ConstantFlow(depth.size(), 1, 0), options);
  // Stride 2: columns 4, 6, ..., 30 (14) on rows 0, 2, ..., 22 (12).
  EXPECT_EQ(stats.candidates, 14 * 12);
  // Columns 20..30 land on 21..31 (6 columns), none outside (x + 1 <= 31).
  EXPECT_EQ(stats.not_water, 6 * 12);
  EXPECT_EQ(stats.accepted, 8 * 12);
}

TEST(FlowLiftingTest, PixelsWithoutSurfaceAreNotLifted) {
  const Camera camera = CenteredCamera(16, 12, 20);
  cv::Mat depth(12, 16, CV_32FC1, cv::Scalar(4));
  depth.rowRange(0, 6) = 0.0f;  // sky: alpha below threshold
  const LiftingView view{&camera, depth, Ones(camera)};
  LiftingOptions options;
  options.stride = 1;
  const auto [samples, stats] =
      Lift(view, view, ConstantFlow(depth.size(), 0, 0), options);
  EXPECT_EQ(stats.no_depth, 6 * 16);
  EXPECT_EQ(stats.depth_edge, 16);  // row 6 touches the empty row 5
  EXPECT_EQ(stats.accepted, 5 * 16);
}

// The lifting's two flag choices (--second_end, --flow_image).
TEST(FlowLiftingTest, ParsesItsChoices) {
  EXPECT_EQ(ParseSecondEnd("plane"), SecondEnd::kFacingPlane);
  EXPECT_EQ(ParseSecondEnd("depth"), SecondEnd::kRenderedDepth);
  EXPECT_THROW(ParseSecondEnd("ray"), InputError);
  EXPECT_EQ(ParseFlowImage("frame"), FlowImage::kFrame);
  EXPECT_EQ(ParseFlowImage("fluctuation"), FlowImage::kFluctuation);
  EXPECT_THROW(ParseFlowImage("residual"), InputError);
}

TEST(FlowLiftingTest, FluctuationOfTheRenderedImageIsGray) {
  RenderResult render;
  render.width = 2;
  render.height = 1;
  render.rgb = {0.2, 0.4, 0.6, 0.9, 0.1, 0.0};
  cv::Mat frame(1, 2, CV_32FC3);
  frame.at<cv::Vec3f>(0, 0) = cv::Vec3f(0.2f, 0.4f, 0.6f);
  frame.at<cv::Vec3f>(0, 1) = cv::Vec3f(0.1f, 0.3f, 0.0f);  // clamps
  const cv::Mat f = Fluctuation(frame, render);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f.at<cv::Vec3f>(0, 0)[c], 0.5f, 1e-6);
  }
  EXPECT_NEAR(f.at<cv::Vec3f>(0, 1)[0], 0.0f, 1e-6);
  EXPECT_NEAR(f.at<cv::Vec3f>(0, 1)[1], 0.7f, 1e-6);
  EXPECT_NEAR(f.at<cv::Vec3f>(0, 1)[2], 0.5f, 1e-6);
}

// Half-transparent water, a texture moving by a known shift, over still
// scenery; the static model's render is the scenery behind the water's
// time average. The flow of the frames is pulled toward the scenery's
// zero motion; the flow of the fluctuation follows the water.
TEST(FlowLiftingTest, FluctuationFlowFollowsWaterOverStillScenery) {
  const int w = 160, h = 120;
  const cv::Mat scenery = TwoScaleTexture(w, h, 3, 11);
  const cv::Mat water = TwoScaleTexture(w, h, 3, 12);
  const cv::Mat truth(h, w, CV_32FC2, cv::Scalar(1.5f, -1.0f));
  const cv::Mat first = 0.5 * scenery + 0.5 * WarpByFlow(water, truth);
  const cv::Mat second = 0.5 * scenery + 0.5 * water;
  const cv::Scalar water_mean = cv::mean(water);
  RenderResult still;
  still.width = w;
  still.height = h;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        still.rgb.push_back(0.5 * scenery.at<cv::Vec3f>(y, x)[c] +
                            0.5 * water_mean[c]);
      }
    }
  }
  cv::Mat valid(h, w, CV_8UC1, cv::Scalar(0));
  valid(cv::Rect(12, 12, w - 24, h - 24)) = 255;
  OpticalFlow flow(FlowMethod::kDisMedium);
  const double on_frames = MeanEndpointError(
      flow.ComputePair(first, second).forward, truth, valid);
  const double on_fluctuation = MeanEndpointError(
      flow.ComputePair(Fluctuation(first, still), Fluctuation(second, still))
          .forward,
      truth, valid);
  EXPECT_LT(on_fluctuation, 0.2);
  EXPECT_GT(on_frames, 2 * on_fluctuation);
}

TEST(FlowLiftingTest, DepthMapDividesByAlphaAndMasksEmptyPixels) {
  RenderResult render;
  render.width = 2;
  render.height = 1;
  render.alpha = {0.8, 0.3};
  render.depth = {2.4, 0.9};
  render.extra = {0.4, 0.8, 0.1, 0.2};  // two channels
  const cv::Mat depth = FloatImage(render, ExpectedDepth(render, 0.5));
  EXPECT_FLOAT_EQ(depth.at<float>(0, 0), 3.0f);
  EXPECT_EQ(depth.at<float>(0, 1), 0.0f);
  const cv::Mat extra = FloatImage(render, NormalizedExtra(render, 1, 0.5));
  EXPECT_FLOAT_EQ(extra.at<float>(0, 0), 1.0f);
  EXPECT_EQ(extra.at<float>(0, 1), 0.0f);
}

}  // namespace
}  // namespace es
