// Renders a trained looping model as an animation (Alg. 2, cycle number
// p = 0, so the video loops with period L): PNG frames and an MP4, along
// any of several camera paths, optionally with the 3D tracks of water
// Gaussians drawn over the frames and the x-t slice of a fixed view. The
// stage is core/viz/animation.h.
//
//   es_animate --model DIR --scene DIR --out DIR [--frames 60]
//              [--camera input|fixed|fixed_time|orbit] [--tracks]
//              [--xt_slice ROW|auto] [--device cpu|cuda]

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "apps/common/loop_frames_on.h"
#include "core/base/input_error.h"
#include "core/viz/animation.h"
#include "core/viz/camera_path.h"

constexpr char kUsage[] =
    "Renders a looping animation of a trained model.\n"
    "  es_animate --model DIR --scene DIR --out DIR [--frames 60]\n"
    "             [--camera input|fixed|fixed_time|orbit] [--tracks]\n"
    "             [--xt_slice ROW|auto] [--device cpu|cuda]";

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

es::AnimationOptions OptionsFromFlags() {
  es::AnimationOptions o;
  o.camera = es::ParseCameraMode(FLAGS_camera);
  o.model_dir = FLAGS_model;
  o.scene_dir = FLAGS_scene;
  o.out_dir = FLAGS_out;
  o.scene.image_scale = FLAGS_image_scale;
  if (FLAGS_white_background) o.render.background.setOnes();
  o.frames = FLAGS_frames;
  o.start_frame = FLAGS_start_frame;
  o.anchor_frame = FLAGS_anchor_frame;
  o.time = FLAGS_time;
  o.orbit_degrees = FLAGS_orbit_degrees;
  o.fps = FLAGS_fps;
  o.tracks = FLAGS_tracks;
  o.track_count = FLAGS_track_count;
  o.track_length = FLAGS_track_length;
  o.track_seed = FLAGS_track_seed;
  o.xt_slice = FLAGS_xt_slice;
  o.device = FLAGS_device;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, [] {
    es::AnimationOptions o = OptionsFromFlags();
    const es::ComputeDevice device =
        es::ParseDeviceFlag(FLAGS_device, &o.device_description);
    CheckFlags(o.camera, device);
    es::WriteAnimation(o, es::LoopFramesOn(device));
    return 0;
  });
}
