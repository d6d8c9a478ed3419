#include "core/viz/animation.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/base/input_error.h"
#include "core/io/image_file.h"
#include "core/io/output_dir.h"
#include "core/viz/track_overlay.h"
#include "core/viz/video_writer.h"
#include "core/viz/xt_slice.h"
#include "core/viz/xt_slice_figure.h"

namespace es {
namespace {

// The anchor frame of CameraMode::kFixed.
int AnchorFrame(const Scene& scene, int anchor) {
  if (anchor < 0) {
    if (scene.test.empty()) {
      throw InputError(scene.dir + ": no held-out frames for the default "
                       "anchor view; give --anchor_frame");
    }
    anchor = scene.test.front();
  }
  if (anchor >= static_cast<int>(scene.frames.size())) {
    throw InputError("--anchor_frame " + std::to_string(anchor) +
                     ": the scene has " + std::to_string(scene.frames.size()) +
                     " frames");
  }
  return anchor;
}

// The image row of an x-t slice ROW; -1 for auto (chosen after rendering).
int XtSliceRow(const std::string& xt_slice, int height) {
  if (xt_slice == "auto") return -1;
  int row = -1;
  try {
    size_t used = 0;
    row = std::stoi(xt_slice, &used);
    if (used != xt_slice.size()) row = -2;
  } catch (const std::exception&) {
    row = -2;
  }
  if (row == -2) {
    throw InputError("--xt_slice=" + xt_slice +
                     ": neither a row number nor auto");
  }
  if (row < 0 || row >= height) {
    throw InputError("--xt_slice=" + xt_slice +
                     ": the rendered frames have rows 0.." +
                     std::to_string(height - 1));
  }
  return row;
}

// Writes xt_slice_raw.png and the labelled xt_slice.png (last: the driver
// takes it as the sign that the animation is complete) from the frames
// already written to out_dir/frames.
void WriteXtSlice(const std::string& out_dir, int frames, int row,
                  bool automatic, int cycle_length) {
  XtSlice slice(row);
  cv::Mat first;
  for (int k = 0; k < frames; ++k) {
    const std::string path = out_dir + "/frames/" + AnimationFrameName(k);
    const cv::Mat frame = cv::imread(path, cv::IMREAD_COLOR);
    if (frame.empty()) throw InputError(path + ": cannot read back");
    if (k == 0) first = frame;
    slice.Add(frame);
  }
  const std::string raw = out_dir + "/xt_slice_raw.png";
  WriteImageAtomically(raw, slice.image());
  const std::string title =
      "x-t slice of row " + std::to_string(row) +
      (automatic ? " (auto: the row of most temporal change)" : "") +
      ", loop L = " + std::to_string(cycle_length);
  const std::string path = out_dir + "/xt_slice.png";
  WriteImageAtomically(
      path, XtSliceFigure(first, slice.image(), row, cycle_length, title));
  std::printf("x-t slice of row %d%s -> %s (%s: %d x %d)\n", row,
              automatic ? " (auto)" : "", path.c_str(), raw.c_str(),
              slice.image().cols, slice.image().rows);
}

// One progress line (with ETA) about every 20th of the frames.
void PrintProgress(int done, int frames,
                   std::chrono::steady_clock::time_point start) {
  const int every = std::max(1, frames / 20);
  if (done % every != 0 && done != frames) return;
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  std::printf("frame %d/%d  %.1f s  ETA %.0f s\n", done, frames, seconds,
              seconds / done * (frames - done));
  std::fflush(stdout);
}

// The dynamic Gaussians' center (coordinate-wise median, robust to
// floaters); all Gaussians' when there are no dynamic ones.
Eigen::Vector3d OrbitCenter(const LoopModel& model,
                            const std::string& model_dir) {
  std::vector<int> ids = model.dynamic_index;
  if (ids.empty()) {
    for (int i = 0; i < model.gaussians.size(); ++i) ids.push_back(i);
  }
  if (ids.empty()) throw InputError(model_dir + ": model is empty");
  Eigen::Vector3d center;
  for (int j = 0; j < 3; ++j) {
    std::vector<double> v;
    for (int i : ids) v.push_back(model.gaussians.means[3 * i + j]);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    center[j] = v[v.size() / 2];
  }
  return center;
}

}  // namespace

std::vector<Camera> AnimationCameras(const Scene& scene,
                                     const LoopModel& model,
                                     const AnimationOptions& o) {
  std::vector<Camera> trajectory;
  for (const Frame& f : scene.frames) trajectory.push_back(f.camera);
  switch (o.camera) {
    case CameraMode::kInput:
    case CameraMode::kFixedTime:
      return ResamplePath(trajectory, o.frames);
    case CameraMode::kFixed:
      return std::vector<Camera>(
          o.frames, trajectory[AnchorFrame(scene, o.anchor_frame)]);
    case CameraMode::kOrbit:
      return OrbitPath(trajectory.front(), OrbitCenter(model, o.model_dir),
                       MeanUpDirection(trajectory), o.orbit_degrees, o.frames);
  }
  return {};
}

AnimationResult WriteAnimation(const AnimationOptions& o,
                               const LoopFramesFactory& make_frames) {
  const Scene scene = LoadScene(o.scene_dir, o.scene);
  const LoopModel model = LoadLoopModel(o.model_dir);
  const std::vector<Camera> cameras = AnimationCameras(scene, model, o);
  AnimationResult result;
  const bool xt_auto = o.xt_slice == "auto";
  const int xt_row =
      o.xt_slice.empty() ? -1 : XtSliceRow(o.xt_slice, cameras.front().height);

  PrepareOutputDirectory(o.out_dir, "out");
  VideoWriter video(o.out_dir + "/frames", o.fps);
  std::optional<TrackOverlay> tracks;
  if (o.tracks) {
    tracks.emplace(model, o.out_dir, o.fps, o.track_count, o.track_length,
                   o.track_seed);
  }
  RowChange row_change;  // for an automatic x-t slice

  if (o.device != "cpu")
    std::printf("rendering on %s\n", o.device_description.c_str());
  const std::unique_ptr<LoopFrames> renderer = make_frames(&model, o.render);
  if (tracks && renderer->cpu_renderer() == nullptr) {
    throw InputError("tracks need the frames rendered on the CPU");
  }
  const bool frozen = o.camera == CameraMode::kFixedTime;
  renderer->Start(frozen ? o.time : o.start_frame);
  double render_ms = 0;
  const auto start_time = std::chrono::steady_clock::now();
  for (int k = 0; k < o.frames; ++k) {
    if (k > 0 && !frozen) renderer->Advance();
    const auto start = std::chrono::steady_clock::now();
    const std::vector<double>& rgb = renderer->Rgb(cameras[k]);
    render_ms += std::chrono::duration<double, std::milli>(
                     std::chrono::steady_clock::now() - start)
                     .count();
    const cv::Mat bgr =
        RgbToBgr8(rgb.data(), cameras[k].width, cameras[k].height);
    video.Add(bgr);
    if (xt_auto) row_change.Add(bgr);
    if (tracks) tracks->Add(*renderer->cpu_renderer(), cameras[k], bgr);
    PrintProgress(k + 1, o.frames, start_time);
  }
  result.encoder = video.Finish(o.out_dir + "/animation.mp4");
  result.render_ms_per_frame = render_ms / o.frames;
  std::printf("%d frames (%s camera, period L = %d) -> %s/animation.mp4 "
              "[%s], %.1f ms/frame\n",
              o.frames, CameraModeName(o.camera).c_str(), model.cycle_length,
              o.out_dir.c_str(), result.encoder.c_str(),
              result.render_ms_per_frame);
  if (tracks) tracks->Finish(model.num_dynamic());
  if (!o.xt_slice.empty()) {
    result.xt_row = xt_auto ? row_change.BusiestRow() : xt_row;
    WriteXtSlice(o.out_dir, o.frames, result.xt_row, xt_auto,
                 model.cycle_length);
  }
  return result;
}

}  // namespace es
