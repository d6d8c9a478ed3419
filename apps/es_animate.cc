// Renders a trained looping model as an animation (Alg. 2, cycle number
// p = 0, so the video loops with period L): PNG frames and an MP4, along
// any of several camera paths, optionally with the 3D tracks of water
// Gaussians drawn over the frames and the x-t slice of a fixed view.
//
//   es_animate --model DIR --scene DIR --out DIR [--frames 60]
//              [--camera input|fixed|fixed_time|orbit] [--tracks]
//              [--xt_slice ROW|auto] [--device cpu|cuda]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gflags/gflags.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "apps/common/loop_frames_on.h"
#include "apps/common/scaled_scene.h"
#include "core/io/image_file.h"
#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "core/io/scene.h"
#include "core/loop/loop_frames.h"
#include "core/loop/loop_renderer.h"
#include "core/loop/loop_model.h"
#include "core/viz/camera_path.h"
#include "core/viz/tracks.h"
#include "core/viz/video_writer.h"
#include "core/viz/xt_slice.h"
#include "core/viz/xt_slice_figure.h"

DEFINE_string(model, "", "Trained looping model directory (es_train --out).");
DEFINE_string(scene, "", "Scene directory the model was trained on "
              "(its cameras and held-out split).");
DEFINE_string(out, "", "Output directory: frames/, animation.mp4, and "
              "tracks/ + tracks.mp4 or xt_slice.png + xt_slice_raw.png when "
              "asked for.");
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
DEFINE_string(xt_slice, "", "With --camera fixed: image row ROW of every "
              "frame stacked over time, as xt_slice_raw.png (one pixel row "
              "per frame) and xt_slice.png (enlarged, with axes, the sliced "
              "row shown on the first frame and loop boundaries marked). "
              "ROW is a number, or auto: the row through the most temporal "
              "change, i.e. through moving water. Empty: off.");
DEFINE_string(device, "cpu",
              "Where the frames render: cpu, or cuda (the first NVIDIA GPU; "
              "needs a build with the CUDA backend, -DES_CUDA=ON or AUTO "
              "with the CUDA toolkit installed): Alg. 2 and the rasterizer "
              "run there and only each finished image comes back. --tracks "
              "needs cpu.");

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

// The image row of --xt_slice ROW; -1 for auto (chosen after rendering).
int XtSliceRow(int height) {
  if (FLAGS_xt_slice == "auto") return -1;
  int row = -1;
  try {
    size_t used = 0;
    row = std::stoi(FLAGS_xt_slice, &used);
    if (used != FLAGS_xt_slice.size()) row = -2;
  } catch (const std::exception&) {
    row = -2;
  }
  if (row == -2) {
    throw es::InputError("--xt_slice=" + FLAGS_xt_slice +
                         ": neither a row number nor auto");
  }
  if (row < 0 || row >= height) {
    throw es::InputError("--xt_slice=" + FLAGS_xt_slice +
                         ": the rendered frames have rows 0.." +
                         std::to_string(height - 1));
  }
  return row;
}

// Writes xt_slice_raw.png and the labelled xt_slice.png (last: the driver
// takes it as the sign that the animation is complete) from the frames
// already written to frame_dir.
void WriteXtSlice(const std::string& frame_dir, int frames, int row,
                  bool automatic, int cycle_length) {
  es::XtSlice slice(row);
  cv::Mat first;
  for (int k = 0; k < frames; ++k) {
    const std::string path = frame_dir + "/" + es::AnimationFrameName(k);
    const cv::Mat frame = cv::imread(path, cv::IMREAD_COLOR);
    if (frame.empty()) throw es::InputError(path + ": cannot read back");
    if (k == 0) first = frame;
    slice.Add(frame);
  }
  const std::string raw = FLAGS_out + "/xt_slice_raw.png";
  es::WriteImageAtomically(raw, slice.image());
  const std::string title =
      "x-t slice of row " + std::to_string(row) +
      (automatic ? " (auto: the row of most temporal change)" : "") +
      ", loop L = " + std::to_string(cycle_length);
  const std::string path = FLAGS_out + "/xt_slice.png";
  es::WriteImageAtomically(
      path, es::XtSliceFigure(first, slice.image(), row, cycle_length, title));
  std::printf("x-t slice of row %d%s -> %s (%s: %d x %d)\n", row,
              automatic ? " (auto)" : "", path.c_str(), raw.c_str(),
              slice.image().cols, slice.image().rows);
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

void CheckFlags(es::CameraMode mode, es::ComputeDevice device) {
  es::RequireFlag("model", FLAGS_model);
  es::RequireFlag("scene", FLAGS_scene);
  es::RequireFlag("out", FLAGS_out);
  es::RequireAtLeast("frames", FLAGS_frames, 1);
  es::RequireAtLeast("start_frame", FLAGS_start_frame, 0);
  es::RequireAtLeast("anchor_frame", FLAGS_anchor_frame, -1);
  es::RequirePositive("fps", FLAGS_fps);
  es::RequirePositive("image_scale", FLAGS_image_scale);
  es::RequirePositive("orbit_degrees", FLAGS_orbit_degrees);
  es::RequireAtLeast("track_count", FLAGS_track_count, 1);
  es::RequireAtLeast("track_length", FLAGS_track_length, 2);
  if (!FLAGS_xt_slice.empty() && mode != es::CameraMode::kFixed) {
    throw es::InputError("--xt_slice needs --camera fixed (a moving camera "
                         "has no meaningful x-t slice)");
  }
  if (FLAGS_tracks && device == es::ComputeDevice::kCuda) {
    throw es::InputError("--tracks needs --device cpu (on the GPU the "
                         "Gaussians' positions stay there)");
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

// One progress line (with ETA) about every 20th of the frames.
void PrintProgress(int done, std::chrono::steady_clock::time_point start) {
  const int every = std::max(1, FLAGS_frames / 20);
  if (done % every != 0 && done != FLAGS_frames) return;
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  std::printf("frame %d/%d  %.1f s  ETA %.0f s\n", done, FLAGS_frames,
              seconds, seconds / done * (FLAGS_frames - done));
  std::fflush(stdout);
}

int Run() {
  const es::CameraMode mode = es::ParseCameraMode(FLAGS_camera);
  std::string device_name;
  const es::ComputeDevice device =
      es::ParseDeviceFlag(FLAGS_device, &device_name);
  CheckFlags(mode, device);
  es::RenderOptions options;
  if (FLAGS_white_background) options.background.setOnes();
  const es::Scene scene = es::LoadScaledScene(FLAGS_scene, FLAGS_image_scale);
  const es::LoopModel model = es::LoadLoopModel(FLAGS_model);
  const std::vector<es::Camera> cameras =
      CameraPath(scene, model, mode, FLAGS_frames);
  const bool xt_auto = FLAGS_xt_slice == "auto";
  const int xt_row =
      FLAGS_xt_slice.empty() ? -1 : XtSliceRow(cameras.front().height);

  es::PrepareOutputDirectory(FLAGS_out, "out");
  es::VideoWriter video(FLAGS_out + "/frames", FLAGS_fps);
  std::optional<TrackOverlay> tracks;
  if (FLAGS_tracks) tracks.emplace(model);
  es::RowChange row_change;  // for --xt_slice auto

  if (device == es::ComputeDevice::kCuda)
    std::printf("rendering on %s\n", device_name.c_str());
  const std::unique_ptr<es::LoopFrames> renderer =
      es::LoopFramesOn(device, &model, options);
  const bool frozen = mode == es::CameraMode::kFixedTime;
  renderer->Start(frozen ? FLAGS_time : FLAGS_start_frame);
  double render_ms = 0;
  const auto start_time = std::chrono::steady_clock::now();
  for (int k = 0; k < FLAGS_frames; ++k) {
    if (k > 0 && !frozen) renderer->Advance();
    const auto start = std::chrono::steady_clock::now();
    const std::vector<double>& rgb = renderer->Rgb(cameras[k]);
    render_ms += std::chrono::duration<double, std::milli>(
                     std::chrono::steady_clock::now() - start)
                     .count();
    const cv::Mat bgr =
        es::RgbToBgr8(rgb.data(), cameras[k].width, cameras[k].height);
    video.Add(bgr);
    if (xt_auto) row_change.Add(bgr);
    if (tracks) tracks->Add(*renderer->cpu_renderer(), cameras[k], bgr);
    PrintProgress(k + 1, start_time);
  }
  const std::string encoder = video.Finish(FLAGS_out + "/animation.mp4");
  std::printf("%d frames (%s camera, period L = %d) -> %s/animation.mp4 "
              "[%s], %.1f ms/frame\n",
              FLAGS_frames, FLAGS_camera.c_str(), model.cycle_length,
              FLAGS_out.c_str(), encoder.c_str(), render_ms / FLAGS_frames);
  if (tracks) tracks->Finish(model.num_dynamic());
  if (!FLAGS_xt_slice.empty()) {
    WriteXtSlice(FLAGS_out + "/frames", FLAGS_frames,
                 xt_auto ? row_change.BusiestRow() : xt_row, xt_auto,
                 model.cycle_length);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(
      argc, argv,
      "Renders a looping animation of a trained model.\n"
      "  es_animate --model DIR --scene DIR --out DIR [--frames 60]\n"
      "             [--camera input|fixed|fixed_time|orbit] [--tracks]\n"
      "             [--xt_slice ROW|auto] [--device cpu|cuda]",
      Run);
}
