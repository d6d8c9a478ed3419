#include "core/flow/flow_lifting.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/base/parse_choice.h"
#include "core/render/dynamic_probability_view.h"
#include "core/render/render_maps.h"

namespace es {
namespace {

// Bilinear lookup at continuous index coordinates (pixel (j, i) at (j, i));
// the caller keeps (x, y) inside [0, W - 1] x [0, H - 1].
template <typename T>
T Bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), std::max(image.cols - 2, 0));
  const int y0 = std::min(static_cast<int>(y), std::max(image.rows - 2, 0));
  const int x1 = std::min(x0 + 1, image.cols - 1);
  const int y1 = std::min(y0 + 1, image.rows - 1);
  const double ax = x - x0, ay = y - y0;
  const T& a = image.at<T>(y0, x0);
  const T& b = image.at<T>(y0, x1);
  const T& c = image.at<T>(y1, x0);
  const T& d = image.at<T>(y1, x1);
  return (a * (1 - ax) + b * ax) * (1 - ay) + (c * (1 - ax) + d * ax) * ay;
}

enum class DepthCheck { kOk, kNoDepth, kEdge };

// Whether the depth around (x, y) is a single smooth surface: the 2x2
// bilinear support has a surface and the 3x3 neighbourhood of the nearest
// pixel varies by at most max_rel_jump relative to its nearest depth.
DepthCheck CheckDepth(const cv::Mat& depth, double x, double y,
                      double max_rel_jump) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, depth.cols - 1);
  const int y1 = std::min(y0 + 1, depth.rows - 1);
  if (depth.at<float>(y0, x0) <= 0 || depth.at<float>(y0, x1) <= 0 ||
      depth.at<float>(y1, x0) <= 0 || depth.at<float>(y1, x1) <= 0) {
    return DepthCheck::kNoDepth;
  }
  const int cx = static_cast<int>(std::lround(x));
  const int cy = static_cast<int>(std::lround(y));
  float lo = depth.at<float>(cy, cx), hi = lo;
  for (int yy = std::max(cy - 1, 0); yy <= std::min(cy + 1, depth.rows - 1);
       ++yy) {
    for (int xx = std::max(cx - 1, 0); xx <= std::min(cx + 1, depth.cols - 1);
         ++xx) {
      const float d = depth.at<float>(yy, xx);
      if (d <= 0) return DepthCheck::kEdge;  // border of the surface
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  return hi - lo > max_rel_jump * lo ? DepthCheck::kEdge : DepthCheck::kOk;
}

// World point at camera depth z along the ray through index coords (x, y).
Eigen::Vector3d UnprojectToWorld(const Camera& camera, double x, double y,
                                 double z) {
  const Eigen::Vector3d x_cam = camera.Unproject(x + 0.5, y + 0.5, z);
  return camera.R().transpose() * (x_cam - camera.t_cw);
}

// Where the ray of `camera` through index coords (x, y) meets the plane
// through `point` with normal `normal`; nullopt when the ray runs (nearly)
// parallel to the plane or meets it behind the camera.
std::optional<Eigen::Vector3d> IntersectPlane(const Camera& camera, double x,
                                              double y,
                                              const Eigen::Vector3d& point,
                                              const Eigen::Vector3d& normal) {
  const Eigen::Vector3d center = camera.Center();
  const Eigen::Vector3d dir =
      camera.R().transpose() * camera.Unproject(x + 0.5, y + 0.5, 1.0);
  const double denom = normal.dot(dir);
  if (std::abs(denom) < 1e-6 * dir.norm()) return std::nullopt;
  const double s = normal.dot(point - center) / denom;
  if (!(s > 0)) return std::nullopt;
  return center + s * dir;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                       start)
      .count();
}

// The flag spellings, in the order an error lists them.
constexpr Choice<SecondEnd> kSecondEnds[] = {
    {"plane", SecondEnd::kFacingPlane}, {"depth", SecondEnd::kRenderedDepth}};
constexpr Choice<FlowImage> kFlowImages[] = {
    {"frame", FlowImage::kFrame}, {"fluctuation", FlowImage::kFluctuation}};

}  // namespace

cv::Mat Fluctuation(const cv::Mat& frame, const RenderResult& render) {
  CHECK_EQ(frame.type(), CV_32FC3);
  CHECK_EQ(frame.cols, render.width);
  CHECK_EQ(frame.rows, render.height);
  cv::Mat out(frame.rows, frame.cols, CV_32FC3);
  for (int y = 0; y < frame.rows; ++y) {
    const cv::Vec3f* in = frame.ptr<cv::Vec3f>(y);
    cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
    const double* rgb =
        render.rgb.data() + 3 * static_cast<size_t>(y) * frame.cols;
    for (int x = 0; x < frame.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double v = in[x][c] - rgb[3 * x + c] + 0.5;
        o[x][c] = static_cast<float>(std::clamp(v, 0.0, 1.0));
      }
    }
  }
  return out;
}

cv::Mat FloatImage(const RenderResult& render,
                   const std::vector<double>& map) {
  CHECK_EQ(map.size(), static_cast<size_t>(render.height) * render.width);
  cv::Mat image;
  cv::Mat(render.height, render.width, CV_64FC1,
          const_cast<double*>(map.data()))
      .convertTo(image, CV_32F);
  return image;
}

void LiftingStats::Add(const LiftingStats& o) {
  candidates += o.candidates;
  no_depth += o.no_depth;
  depth_edge += o.depth_edge;
  outside += o.outside;
  inconsistent += o.inconsistent;
  not_water += o.not_water;
  accepted += o.accepted;
}

namespace {

// Whether LiftFlow would look at any pixel of `water` (the first frame's):
// one on its stride grid at or above the threshold. Pairs without one give
// no samples, so their optical flow is not computed.
bool HasWaterCandidate(const cv::Mat& water, const LiftingOptions& options) {
  for (int y = 0; y < water.rows; y += options.stride) {
    for (int x = 0; x < water.cols; x += options.stride) {
      if (water.at<float>(y, x) >= options.water_threshold) return true;
    }
  }
  return false;
}

}  // namespace

void LiftFlow(const LiftingView& first, const LiftingView& second,
              const FlowPair& flow, const LiftingOptions& options,
              std::vector<SceneFlowSample>* samples, LiftingStats* stats) {
  CHECK(first.camera != nullptr && second.camera != nullptr);
  CHECK(samples != nullptr);
  CHECK_GE(options.stride, 1);
  CHECK_GE(options.frame_gap, 1);
  CHECK(options.line_of_sight_weight >= 0 &&
        options.line_of_sight_weight <= 1);
  const cv::Size size = first.depth.size();
  for (const cv::Mat* m : {&first.depth, &first.water, &second.depth,
                           &second.water, &flow.forward, &flow.backward}) {
    CHECK_EQ(m->size(), size);
  }
  CHECK_EQ(first.depth.type(), CV_32FC1);
  CHECK_EQ(second.depth.type(), CV_32FC1);
  CHECK_EQ(first.water.type(), CV_32FC1);
  CHECK_EQ(second.water.type(), CV_32FC1);
  CHECK_EQ(flow.forward.type(), CV_32FC2);
  CHECK_EQ(flow.backward.type(), CV_32FC2);

  LiftingStats s;
  const double max_fb2 = options.max_fb_error_px * options.max_fb_error_px;
  for (int y = 0; y < size.height; y += options.stride) {
    for (int x = 0; x < size.width; x += options.stride) {
      if (first.water.at<float>(y, x) < options.water_threshold) continue;
      ++s.candidates;
      const DepthCheck d0 =
          CheckDepth(first.depth, x, y, options.max_rel_depth_jump);
      if (d0 == DepthCheck::kNoDepth) { ++s.no_depth; continue; }
      if (d0 == DepthCheck::kEdge) { ++s.depth_edge; continue; }

      const cv::Vec2f f = flow.forward.at<cv::Vec2f>(y, x);
      const double x1 = x + f[0], y1 = y + f[1];
      if (!(x1 >= 0 && y1 >= 0 && x1 <= size.width - 1 &&
            y1 <= size.height - 1)) {
        ++s.outside;
        continue;
      }
      const cv::Vec2f b = Bilinear<cv::Vec2f>(flow.backward, x1, y1);
      const double fb_x = f[0] + b[0], fb_y = f[1] + b[1];
      if (fb_x * fb_x + fb_y * fb_y > max_fb2) { ++s.inconsistent; continue; }
      if (second.water.at<float>(static_cast<int>(std::lround(y1)),
                                 static_cast<int>(std::lround(x1))) <
          options.water_threshold) {
        ++s.not_water;
        continue;
      }
      const Eigen::Vector3d p0 = UnprojectToWorld(
          *first.camera, x, y, first.depth.at<float>(y, x));
      Eigen::Vector3d p1;
      Eigen::Vector3d unseen = Eigen::Vector3d::Zero();
      if (options.second_end == SecondEnd::kFacingPlane) {
        const Eigen::Vector3d line_of_sight =
            (p0 - first.camera->Center()).normalized();
        const std::optional<Eigen::Vector3d> hit =
            IntersectPlane(*second.camera, x1, y1, p0, line_of_sight);
        if (!hit) { ++s.no_depth; continue; }
        p1 = *hit;
        unseen =
            std::sqrt(1.0 - options.line_of_sight_weight) * line_of_sight;
      } else {
        const DepthCheck d1 =
            CheckDepth(second.depth, x1, y1, options.max_rel_depth_jump);
        if (d1 == DepthCheck::kNoDepth) { ++s.no_depth; continue; }
        if (d1 == DepthCheck::kEdge) { ++s.depth_edge; continue; }
        p1 = UnprojectToWorld(*second.camera, x1, y1,
                              Bilinear<float>(second.depth, x1, y1));
      }
      samples->push_back({p0, (p1 - p0) / options.frame_gap, unseen});
      ++s.accepted;
    }
  }
  if (stats != nullptr) stats->Add(s);
}

SecondEnd ParseSecondEnd(const std::string& name) {
  return ParseChoice("second end", name, kSecondEnds);
}
const char* SecondEndName(SecondEnd end) {
  return ChoiceName(end, kSecondEnds);
}

FlowImage ParseFlowImage(const std::string& name) {
  return ParseChoice("flow image", name, kFlowImages);
}
const char* FlowImageName(FlowImage image) {
  return ChoiceName(image, kFlowImages);
}

WaterSource ParseWaterSource(const std::string& name) {
  return ParseChoice<WaterSource>("water source", name,
                                  {{"auto", WaterSource::kAuto},
                                   {"masks", WaterSource::kMasks},
                                   {"model", WaterSource::kModel}});
}

SceneFlowResult LiftSceneFlow(const Scene& scene, const GaussianSet& model,
                              const SceneFlowOptions& options) {
  using Clock = std::chrono::steady_clock;
  SceneFlowResult result;
  if (options.water == WaterSource::kMasks && !scene.has_masks) {
    throw InputError(scene.dir +
                     ": no masks/ directory, but water pixels were asked to "
                     "come from masks; use the static model's dynamic "
                     "channel instead (water source 'model' or 'auto')");
  }
  result.used_masks =
      scene.has_masks && options.water != WaterSource::kModel;

  const int num_frames = static_cast<int>(scene.frames.size());
  std::vector<bool> usable(num_frames, false);
  for (int i : scene.train) usable[i] = true;
  if (options.use_test_frames) {
    for (int i : scene.test) usable[i] = true;
  }
  // Samples are motion per frame: the ends of a pair must be frame_gap
  // video frames apart, not merely neighbours among the frames COLMAP
  // registered.
  const int gap = options.lifting.frame_gap;
  CHECK_GE(gap, 1);
  std::map<int, int> frame_at_time;  // time index -> frame
  for (int i = 0; i < num_frames; ++i)
    if (usable[i]) frame_at_time[scene.frames[i].time_index] = i;
  std::vector<std::pair<int, int>> pairs;
  for (const auto& [time, i] : frame_at_time) {
    const auto second = frame_at_time.find(time + gap);
    if (second != frame_at_time.end()) pairs.emplace_back(i, second->second);
  }
  if (pairs.empty()) {
    throw InputError(scene.dir + ": no two training frames are " +
                     std::to_string(gap) +
                     " video frame(s) apart, so there is no optical flow "
                     "to lift");
  }
  result.num_pairs = static_cast<int>(pairs.size());

  std::vector<double> dynamic_probability;
  const SplatView splats = DynamicProbabilityView(model, &dynamic_probability);
  Rasterizer rasterizer;
  RenderResult render;

  struct RenderedFrame {
    int index = -1;
    cv::Mat depth, water, flow_input;
  };
  auto render_frame = [&](int i) {
    const auto start = Clock::now();
    const Frame& frame = scene.frames[i];
    rasterizer.Forward(frame.camera, splats, options.render, &render);
    RenderedFrame r;
    r.index = i;
    r.depth = FloatImage(render, ExpectedDepth(render, options.min_alpha));
    r.water = result.used_masks
                  ? frame.mask
                  : FloatImage(render,
                               NormalizedExtra(render, 0, options.min_alpha));
    r.flow_input = options.image == FlowImage::kFluctuation
                       ? Fluctuation(frame.image, render)
                       : frame.image;
    result.render_seconds += SecondsSince(start);
    return r;
  };

  OpticalFlow flow(options.method);
  std::optional<RenderedFrame> previous;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    const RenderedFrame first = previous && previous->index == i
                                    ? *previous
                                    : render_frame(i);
    const RenderedFrame second = render_frame(j);
    previous = second;
    if (first.water.type() == CV_32FC1 &&
        !HasWaterCandidate(first.water, options.lifting)) {
      ++result.num_dry_pairs;
      if (options.progress) {
        options.progress(static_cast<int>(k), result.num_pairs,
                         scene.frames[i].camera.image_name,
                         scene.frames[j].camera.image_name, 0);
      }
      continue;
    }

    auto start = Clock::now();
    const FlowPair pair =
        flow.ComputePair(first.flow_input, second.flow_input);
    result.flow_seconds += SecondsSince(start);

    start = Clock::now();
    const LiftingView a{&scene.frames[i].camera, first.depth, first.water};
    const LiftingView b{&scene.frames[j].camera, second.depth, second.water};
    const size_t before = result.samples.size();
    LiftFlow(a, b, pair, options.lifting, &result.samples, &result.stats);
    result.lift_seconds += SecondsSince(start);
    if (options.progress) {
      options.progress(static_cast<int>(k), result.num_pairs,
                       scene.frames[i].camera.image_name,
                       scene.frames[j].camera.image_name,
                       static_cast<long>(result.samples.size() - before));
    }
  }
  return result;
}

}  // namespace es
