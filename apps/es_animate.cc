// Renders a trained looping model as an animation (Alg. 2, cycle number
// p = 0, so the video loops with period L): PNG frames and an MP4, along
// any of several camera paths, optionally with the 3D tracks of water
// Gaussians drawn over the frames and the x-t slice of a fixed view.
//
//   es_animate --model DIR --scene DIR --out DIR [--frames 60]
//              [--camera input|fixed|fixed_time|orbit] [--tracks]
//              [--xt_slice ROW|auto]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gflags/gflags.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "apps/common/app_main.h"
#include "core/io/atomic_file.h"
#include "core/io/input_error.h"
#include "core/io/scene.h"
#include "core/loop/loop_renderer.h"
#include "core/model/loop_model.h"
#include "core/viz/camera_path.h"
#include "core/viz/tracks.h"
#include "core/viz/video_writer.h"
#include "core/viz/xt_slice.h"

DEFINE_string(model, "", "Trained looping model directory (es_train --out).");
DEFINE_string(scene, "", "Scene directory the model was trained on "
              "(its cameras and held-out split).");
DEFINE_string(out, "", "Output directory: frames/, animation.mp4, and "
              "tracks/ + tracks.mp4 or xt_slice.png when asked for.");
DEFINE_int32(frames, 60, "Number of frames to render (any number: the "
             "animation loops with period L).");
DEFINE_int32(start_frame, 0, "Animation frame of the first output frame.");
DEFINE_string(camera, "input",
              "Camera path: input (the video's trajectory, resampled to "
              "--frames poses), fixed (one held-out anchor view), "
              "fixed_time (time frozen at --time, camera along the input "
              "trajectory) or orbit (around the water's center).");
DEFINE_int32(anchor_frame, -1, "Frame whose camera --camera fixed uses; "
             "-1: the first held-out (test) frame.");
DEFINE_int32(time, 0, "Animation frame --camera fixed_time freezes.");
DEFINE_double(orbit_degrees, 30.0,
              "--camera orbit: swing +-degrees/2 around the center and "
              "back; >= 360 goes once around.");
DEFINE_double(fps, 24.0, "Frame rate of the MP4.");
DEFINE_double(image_scale, 1.0, "Render at this fraction of the scene's "
              "image size.");
DEFINE_bool(white_background, false, "Render on white instead of black "
            "(as the model was trained: es_train --white_background).");
DEFINE_bool(tracks, false, "Also write tracks/ and tracks.mp4: the frames "
            "with the projected 3D tracks of --track_count water Gaussians "
            "(their last --track_length positions, colored by time).");
DEFINE_int32(track_count, 300, "Water Gaussians whose tracks are drawn.");
DEFINE_int32(track_length, 10, "Positions per track polyline.");
DEFINE_uint64(track_seed, 1, "Seed of the tracked subset.");
DEFINE_string(xt_slice, "", "With --camera fixed: write xt_slice.png, image "
              "row ROW of every frame stacked over time. ROW is a number, "
              "or auto: the row with the most water in the anchor frame's "
              "mask (the middle row without masks). Empty: off.");

namespace {

// The dynamic Gaussians' center (coordinate-wise median, robust to
// floaters); all Gaussians' when there are no dynamic ones.
Eigen::Vector3d OrbitCenter(const es::LoopModel& model) {
  std::vector<int> ids = model.dynamic_index;
  if (ids.empty()) {
    for (int i = 0; i < model.gaussians.size(); ++i) ids.push_back(i);
  }
  if (ids.empty()) throw es::InputError(FLAGS_model + ": model is empty");
  Eigen::Vector3d center;
  for (int j = 0; j < 3; ++j) {
    std::vector<double> v;
    for (int i : ids) v.push_back(model.gaussians.means[3 * i + j]);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    center[j] = v[v.size() / 2];
  }
  return center;
}

// The anchor frame of --camera fixed.
int AnchorFrame(const es::Scene& scene) {
  int anchor = FLAGS_anchor_frame;
  if (anchor < 0) {
    if (scene.test.empty()) {
      throw es::InputError(FLAGS_scene + ": no held-out frames for the "
                           "default anchor view; give --anchor_frame");
    }
    anchor = scene.test.front();
  }
  if (anchor >= static_cast<int>(scene.frames.size())) {
    throw es::InputError("--anchor_frame " + std::to_string(anchor) +
                         ": the scene has " +
                         std::to_string(scene.frames.size()) + " frames");
  }
  return anchor;
}

// The image row of --xt_slice.
int XtSliceRow(const es::Frame& anchor) {
  if (FLAGS_xt_slice != "auto") {
    try {
      size_t used = 0;
      const int row = std::stoi(FLAGS_xt_slice, &used);
      if (used == FLAGS_xt_slice.size()) return row;
    } catch (const std::exception&) {
    }
    throw es::InputError("--xt_slice: '" + FLAGS_xt_slice +
                         "' is neither a row number nor auto");
  }
  if (anchor.mask.empty()) return anchor.camera.height / 2;
  cv::Mat water;
  cv::reduce(anchor.mask, water, 1, cv::REDUCE_SUM, CV_64F);
  cv::Point best;
  cv::minMaxLoc(water, nullptr, nullptr, nullptr, &best);
  return best.y;
}

std::vector<es::Camera> CameraPath(const es::Scene& scene,
                                   const es::LoopModel& model,
                                   es::CameraMode mode, int count) {
  std::vector<es::Camera> trajectory;
  for (const es::Frame& f : scene.frames) trajectory.push_back(f.camera);
  switch (mode) {
    case es::CameraMode::kInput:
    case es::CameraMode::kFixedTime:
      return es::ResamplePath(trajectory, count);
    case es::CameraMode::kFixed:
      return std::vector<es::Camera>(count, trajectory[AnchorFrame(scene)]);
    case es::CameraMode::kOrbit:
      return es::OrbitPath(trajectory.front(), OrbitCenter(model),
                           es::MeanUpDirection(trajectory),
                           FLAGS_orbit_degrees, count);
  }
  return {};
}

void CheckFlags(es::CameraMode mode) {
  if (FLAGS_model.empty() || FLAGS_scene.empty() || FLAGS_out.empty()) {
    throw es::InputError("--model, --scene and --out are required");
  }
  if (FLAGS_frames < 1) throw es::InputError("--frames must be >= 1");
  if (FLAGS_start_frame < 0) throw es::InputError("--start_frame must be >= 0");
  if (!(FLAGS_fps > 0)) throw es::InputError("--fps must be positive");
  if (FLAGS_track_length < 2) {
    throw es::InputError("--track_length must be >= 2");
  }
  if (!FLAGS_xt_slice.empty() && mode != es::CameraMode::kFixed) {
    throw es::InputError("--xt_slice needs --camera fixed (a moving camera "
                         "has no meaningful x-t slice)");
  }
  if (mode == es::CameraMode::kFixedTime && FLAGS_time < 0) {
    throw es::InputError("--time must be >= 0");
  }
}

// --tracks: the recent positions of a seeded subset of the water Gaussians
// drawn over each frame, into their own video.
class TrackOverlay {
 public:
  explicit TrackOverlay(const es::LoopModel& model)
      : video_(FLAGS_out + "/tracks", FLAGS_fps),
        tracked_(es::SelectTrackSubset(model.num_dynamic(), FLAGS_track_count,
                                       FLAGS_track_seed)),
        history_(static_cast<int>(tracked_.size()), FLAGS_track_length),
        positions_(3 * tracked_.size()) {}

  void Add(const es::LoopRenderer& renderer, const es::Camera& camera,
           const cv::Mat& bgr) {
    const std::vector<double>& x = renderer.positions();
    const std::vector<int>& cycle = renderer.cycle_indices();
    std::vector<bool> restarted(tracked_.size(), false);
    for (size_t i = 0; i < tracked_.size(); ++i) {
      std::copy_n(&x[3 * tracked_[i]], 3, &positions_[3 * i]);
      // A cycle index that did not move forward by one is a reset.
      restarted[i] = !previous_cycle_.empty() &&
                     cycle[tracked_[i]] != previous_cycle_[tracked_[i]] + 1;
    }
    previous_cycle_ = cycle;
    history_.Push(positions_.data(), restarted);
    cv::Mat overlay = bgr.clone();
    history_.Draw(camera, &overlay);
    video_.Add(overlay);
  }

  void Finish(int num_dynamic) {
    video_.Finish(FLAGS_out + "/tracks.mp4");
    std::printf("tracks of %zu of %d water Gaussians -> %s/tracks.mp4\n",
                tracked_.size(), num_dynamic, FLAGS_out.c_str());
  }

 private:
  es::VideoWriter video_;
  std::vector<int> tracked_;
  es::TrackHistory history_;
  std::vector<double> positions_;
  std::vector<int> previous_cycle_;
};

void WriteXtSlice(const es::XtSlice& slice) {
  const std::string path = FLAGS_out + "/xt_slice.png";
  std::vector<uchar> png;
  if (!cv::imencode(".png", slice.image(), png)) {
    throw es::InputError(path + ": cannot encode the x-t slice");
  }
  es::WriteFileAtomically(path, [&png](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), png.size());
  });
  std::printf("x-t slice of row %d -> %s (%d x %d)\n", slice.row(),
              path.c_str(), slice.image().cols, slice.image().rows);
}

int Run() {
  const es::CameraMode mode = es::ParseCameraMode(FLAGS_camera);
  CheckFlags(mode);
  es::RenderOptions options;
  if (FLAGS_white_background) options.background.setOnes();
  es::SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const es::Scene scene = es::LoadScene(FLAGS_scene, scene_options);
  const es::LoopModel model = es::LoadLoopModel(FLAGS_model);
  const std::vector<es::Camera> cameras =
      CameraPath(scene, model, mode, FLAGS_frames);

  std::filesystem::create_directories(FLAGS_out);
  es::VideoWriter video(FLAGS_out + "/frames", FLAGS_fps);
  std::optional<TrackOverlay> tracks;
  if (FLAGS_tracks) tracks.emplace(model);
  std::optional<es::XtSlice> slice;
  if (!FLAGS_xt_slice.empty()) {
    slice.emplace(XtSliceRow(scene.frames[AnchorFrame(scene)]));
  }

  es::LoopRenderer renderer(&model, options);
  const bool frozen = mode == es::CameraMode::kFixedTime;
  renderer.Start(frozen ? FLAGS_time : FLAGS_start_frame);
  double render_ms = 0;
  for (int k = 0; k < FLAGS_frames; ++k) {
    if (k > 0 && !frozen) renderer.Advance();
    const auto start = std::chrono::steady_clock::now();
    const es::RenderResult& r = renderer.Render(cameras[k]);
    render_ms += std::chrono::duration<double, std::milli>(
                     std::chrono::steady_clock::now() - start)
                     .count();
    const cv::Mat bgr = es::RgbToBgr8(r.rgb.data(), r.width, r.height);
    video.Add(bgr);
    if (slice) slice->Add(bgr);
    if (tracks) tracks->Add(renderer, cameras[k], bgr);
  }
  const std::string encoder = video.Finish(FLAGS_out + "/animation.mp4");
  std::printf("%d frames (%s camera, period L = %d) -> %s/animation.mp4 "
              "[%s], %.1f ms/frame\n",
              FLAGS_frames, FLAGS_camera.c_str(), model.cycle_length,
              FLAGS_out.c_str(), encoder.c_str(), render_ms / FLAGS_frames);
  if (tracks) tracks->Finish(model.num_dynamic());
  if (slice) WriteXtSlice(*slice);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(
      argc, argv,
      "Renders a looping animation of a trained model.\n"
      "  es_animate --model DIR --scene DIR --out DIR [--frames 60]\n"
      "             [--camera input|fixed|fixed_time|orbit] [--tracks]\n"
      "             [--xt_slice ROW|auto]",
      Run);
}
