#ifndef EULERSPLAT_CORE_VIZ_ANIMATION_H_
#define EULERSPLAT_CORE_VIZ_ANIMATION_H_

// es_animate's stage: a trained looping model played as an animation
// (Alg. 2, cycle number p = 0, so the video loops with period L) along a
// camera path, written as PNG frames and an MP4, optionally with the 3D
// tracks of water Gaussians drawn over the frames and the x-t slice of a
// fixed view.

#include <cstdint>
#include <string>
#include <vector>

#include "core/io/scene.h"
#include "core/loop/loop_frames_factory.h"
#include "core/loop/loop_model.h"
#include "core/model/camera.h"
#include "core/render/rasterizer.h"
#include "core/viz/camera_path.h"

namespace es {

struct AnimationOptions {
  std::string model_dir;  // a trained looping model (es_train --out)
  std::string scene_dir;  // its scene: the cameras and held-out split
  std::string out_dir;    // frames/, animation.mp4, ... (created)
  SceneOptions scene;
  RenderOptions render;
  int frames = 60;       // any number: the animation loops with period L
  int start_frame = 0;   // animation frame of the first output frame
  CameraMode camera = CameraMode::kInput;
  int anchor_frame = -1;  // kFixed's camera; -1: the first held-out frame
  int time = 0;           // the animation frame kFixedTime freezes
  double orbit_degrees = 30.0;  // kOrbit (camera_path.h's OrbitPath)
  double fps = 24.0;
  // Also tracks/ and tracks.mp4 (CPU frames only: core/viz/track_overlay.h).
  bool tracks = false;
  int track_count = 300;
  int track_length = 10;
  uint64_t track_seed = 1;
  // With kFixed: image row ROW of every frame stacked over time, as
  // xt_slice_raw.png and xt_slice.png; "auto": the row of most temporal
  // change. Empty: none.
  std::string xt_slice;
  // Where the frames render (--device: cpu or cuda); off the CPU,
  // device_description is printed.
  std::string device = "cpu";
  std::string device_description;
};

struct AnimationResult {
  std::string encoder;  // of animation.mp4 (VideoWriter::Finish)
  double render_ms_per_frame = 0;
  int xt_row = -1;  // the sliced row; -1 without a slice
};

// The options.frames cameras of the path options.camera asks for: kOrbit
// circles the dynamic Gaussians' median (all Gaussians' without dynamic
// ones). Throws InputError for an anchor frame past the scene's last, or
// none to default to, and for an orbit around an empty model.
std::vector<Camera> AnimationCameras(const Scene& scene,
                                     const LoopModel& model,
                                     const AnimationOptions& options);

// es_animate: loads the scene and the model, plays the model along the
// camera path with `make_frames`' frames (the CPU's or a device's; tracks
// need the CPU's) and writes out_dir/frames/ and animation.mp4, tracks/ and
// tracks.mp4 when asked, then the x-t slice (xt_slice.png last: the driver
// takes it as the sign that the animation is complete). Throws InputError
// for bad inputs (an x-t slice row outside the frames included) before
// anything is written.
AnimationResult WriteAnimation(
    const AnimationOptions& options,
    const LoopFramesFactory& make_frames = MakeCpuLoopFrames);

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_ANIMATION_H_
