// Exports a trained looping model for other tools and the web:
//   --ply PATH   a standard 3DGS PLY of animation frame --frame with every
//                offset applied (Alg. 2 positions, D's position, opacity
//                and SH offsets), a state the loop really passes through;
//   --web DIR    a self-contained web page that plays the loop forever
//                with orbit controls (the compact loop file, format in
//                core/loop/loop_file.h, a poster of loop frame 0 that the
//                page shows until the player has drawn, and the Spark
//                splat viewer that scripts/setup.sh installs from npm,
//                copied next to it).
//
//   es_export --model DIR [--ply PATH --frame T]
//             [--web DIR --scene DIR [--image_scale S] [--fps 24]]
#include <cstdio>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "core/base/input_error.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/io/scene.h"
#include "core/loop/loop_frame.h"
#include "core/loop/loop_model.h"
#include "core/viz/web_player.h"

constexpr char kUsage[] =
    "Exports a looping model: a PLY of any frame, and a web "
    "page that plays the loop.\n"
    "  es_export --model DIR [--ply PATH --frame T]\n"
    "            [--web DIR --scene DIR [--fps 24]]";

DEFINE_string(model, "", "Trained looping model directory (es_train --out).");
DEFINE_string(ply, "", "Write the splats of animation frame --frame here "
              "as a standard 3DGS PLY (loads in other 3DGS tools).");
DEFINE_int32(frame, 0, "Animation frame of --ply (>= 0; frame t and t + L "
             "are the same).");
DEFINE_string(web, "", "Write the web page that plays the loop into this "
              "directory (serve it over HTTP, e.g. python3 -m http.server "
              "--directory DIR).");
DEFINE_string(scene, "", "With --web: the scene the model was trained on; "
              "its cameras are the page's views (the first is the start).");
DEFINE_double(image_scale, 1.0, "With --web: camera image size as a "
              "fraction of the scene's (as es_animate --image_scale).");
DEFINE_double(fps, 24.0, "With --web: loop frames per second.");
DEFINE_bool(white_background, false, "With --web: white page background "
            "(for a model trained with --white_background).");
DEFINE_string(web_source, ES_WEB_DIR, "The project's web/ folder: the page "
              "(player/) and the npm packages scripts/setup.sh installs "
              "(node_modules/).");

namespace {

int Run() {
  if (FLAGS_model.empty()) throw es::InputError("--model is required");
  if (FLAGS_ply.empty() && FLAGS_web.empty())
    throw es::InputError("nothing to do: give --ply PATH and/or --web DIR");
  if (FLAGS_frame < 0) throw es::InputError("--frame must be >= 0");
  if (!FLAGS_web.empty()) {
    if (FLAGS_scene.empty())
      throw es::InputError("--web needs --scene (the page's camera views)");
    if (!(FLAGS_fps > 0)) throw es::InputError("--fps must be positive");
    if (!(FLAGS_image_scale > 0 && FLAGS_image_scale <= 1))
      throw es::InputError("--image_scale must be in (0, 1]");
  }
  // Before loading anything: the model and the scene take a while to read.
  if (!FLAGS_ply.empty()) es::PrepareOutputFile(FLAGS_ply, "ply");
  if (!FLAGS_web.empty()) es::PrepareOutputDirectory(FLAGS_web, "web");
  const es::LoopModel model = es::LoadLoopModel(FLAGS_model);
  std::printf("model: %d Gaussians, %d water, loop of L = %d frames\n",
              model.gaussians.size(), model.num_dynamic(),
              model.cycle_length);

  if (!FLAGS_ply.empty()) {
    es::WritePly(es::LoopFrameSplats(model, FLAGS_frame), FLAGS_ply);
    std::printf("frame %d (loop frame %d) -> %s\n", FLAGS_frame,
                FLAGS_frame % model.cycle_length, FLAGS_ply.c_str());
  }
  if (!FLAGS_web.empty()) {
    es::SceneOptions scene_options;
    scene_options.image_scale = FLAGS_image_scale;
    const es::Scene scene = es::LoadScene(FLAGS_scene, scene_options);
    std::vector<es::Camera> cameras;
    for (const es::Frame& f : scene.frames) cameras.push_back(f.camera);
    if (cameras.empty()) throw es::InputError(FLAGS_scene + ": no frames");
    es::WebPlayerOptions options;
    options.fps = FLAGS_fps;
    if (FLAGS_white_background) options.background.setOnes();
    options.page_dir = FLAGS_web_source + "/player";
    options.modules_dir = FLAGS_web_source + "/node_modules";
    const int64_t bytes =
        es::ExportWebPlayer(model, cameras, options, FLAGS_web);
    std::printf("web page -> %s/index.html (loop file %.1f MB); play it "
                "with: python3 -m http.server --directory %s, then open "
                "http://localhost:8000/\n",
                FLAGS_web.c_str(), bytes / 1e6, FLAGS_web.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, Run);
}
