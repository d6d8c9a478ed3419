// Measures a trained looping model: held-out PSNR / SSIM (full image and
// water region), motion error against ground truth when the scene has it,
// the loop-seam score of a fixed-view animation, and the per-frame cost of
// playing it with Alg. 1 vs Alg. 2. Writes OUT/eval.json and prints a
// table.
//
//   es_eval --model DIR --scene DIR --out DIR

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "core/io/input_error.h"
#include "core/io/scene.h"
#include "core/model/loop_model.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/train/joint_trainer.h"

DEFINE_string(model, "", "Trained looping model directory (es_train --out).");
DEFINE_string(scene, "", "Scene directory the model was trained on.");
DEFINE_string(out, "", "Output directory for eval.json (created).");
DEFINE_double(image_scale, 1.0, "Evaluate at this fraction of the scene's "
              "image size (as trained).");
DEFINE_bool(white_background, false, "Render on white instead of black "
            "(as the model was trained: es_train --white_background).");
DEFINE_int32(seam_cycles, 3, "Loops of the fixed-view animation the "
             "loop-seam score is measured on (>= 3 for a stable mean).");
DEFINE_int32(anchor_frame, -1, "Frame whose camera the fixed view uses; "
             "-1: the first held-out frame.");
DEFINE_int32(timing_frames, 0, "Frames timed for Alg. 1 vs Alg. 2; 0: 2 L.");

namespace {

// JSON number; NaN and infinity, which JSON lacks, become null.
std::string Number(double v) {
  if (!std::isfinite(v)) return "null";
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", v);
  return text;
}

// JSON string literal.
std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

int Run() {
  if (FLAGS_model.empty() || FLAGS_scene.empty() || FLAGS_out.empty()) {
    throw es::InputError("--model, --scene and --out are required");
  }
  if (FLAGS_seam_cycles < 2) {
    throw es::InputError("--seam_cycles must be >= 2 (a boundary needs a "
                         "cycle on each side)");
  }
  es::RenderOptions options;
  if (FLAGS_white_background) options.background.setOnes();
  es::SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const es::Scene scene = es::LoadScene(FLAGS_scene, scene_options);
  const es::LoopModel model = es::LoadLoopModel(FLAGS_model);
  if (scene.test.empty()) {
    throw es::InputError(FLAGS_scene + ": no held-out frames to evaluate "
                         "(see split.txt)");
  }
  int anchor = FLAGS_anchor_frame >= 0 ? FLAGS_anchor_frame : scene.test[0];
  if (anchor >= static_cast<int>(scene.frames.size())) {
    throw es::InputError("--anchor_frame " + std::to_string(anchor) +
                         " is past the scene's last frame");
  }
  const es::Camera& anchor_camera = scene.frames[anchor].camera;

  const es::LoopMetrics held_out =
      es::EvaluateLoopModel(model, scene.frames, scene.test, options);

  bool has_motion_gt = es::HasMotionGt(FLAGS_scene) && model.motion;
  es::MotionGtMetrics motion;
  if (has_motion_gt) {
    std::vector<Eigen::Vector3d> points;
    for (int i : model.dynamic_index) {
      points.emplace_back(&model.gaussians.means[3 * i]);
    }
    motion = es::EvaluateMotionGt(*model.motion, points,
                                  es::LoadMotionGt(FLAGS_scene));
  }

  const es::LoopSeamScore seam = es::EvaluateLoopSeam(
      model, anchor_camera, FLAGS_seam_cycles, options);
  const int timing_frames =
      FLAGS_timing_frames > 0 ? FLAGS_timing_frames : 2 * model.cycle_length;
  const es::AnimationTiming timing =
      es::TimeAnimation(model, anchor_camera, timing_frames, options);

  std::filesystem::create_directories(FLAGS_out);
  const std::string path = FLAGS_out + "/eval.json";
  std::ofstream json(path);
  json << "{\n"
       << "  \"model\": " << Quoted(FLAGS_model) << ",\n"
       << "  \"scene\": " << Quoted(FLAGS_scene) << ",\n"
       << "  \"gaussians\": " << model.gaussians.size() << ",\n"
       << "  \"dynamic_gaussians\": " << model.num_dynamic() << ",\n"
       << "  \"cycle_length\": " << model.cycle_length << ",\n"
       << "  \"held_out\": {\"frames\": " << held_out.frames
       << ", \"psnr\": " << Number(held_out.psnr)
       << ", \"ssim\": " << Number(held_out.ssim)
       << ", \"psnr_water\": " << Number(held_out.psnr_water)
       << ", \"ssim_water\": " << Number(held_out.ssim_water) << "},\n"
       << "  \"motion_gt\": ";
  if (has_motion_gt) {
    json << "{\"points\": " << motion.num_points
         << ", \"epe\": " << Number(motion.epe)
         << ", \"mean_speed\": " << Number(motion.mean_speed)
         << ", \"rel_epe\": " << Number(motion.rel_epe) << "},\n";
  } else {
    json << "null,\n";
  }
  json << "  \"loop_seam\": {\"anchor_frame\": " << anchor
       << ", \"cycles\": " << FLAGS_seam_cycles
       << ", \"score\": " << Number(seam.score)
       << ", \"boundary_change\": " << Number(seam.boundary_change)
       << ", \"within_change\": " << Number(seam.within_change) << "},\n"
       << "  \"render_time_ms\": {\"frames\": " << timing.frames
       << ", \"alg1_advect\": " << Number(timing.alg1_advect_ms)
       << ", \"alg2_advect\": " << Number(timing.alg2_advect_ms)
       << ", \"render\": " << Number(timing.render_ms)
       << ", \"alg1_frame\": " << Number(timing.alg1_frame_ms())
       << ", \"alg2_frame\": " << Number(timing.alg2_frame_ms())
       << ", \"alg1_alg2_max_position_difference\": "
       << Number(timing.max_position_difference) << "}\n"
       << "}\n";
  json.close();
  if (!json) throw es::InputError(path + ": cannot write");

  std::printf("%s: %d Gaussians (%d dynamic), L = %d\n", FLAGS_model.c_str(),
              model.gaussians.size(), model.num_dynamic(),
              model.cycle_length);
  std::printf("  held-out (%d frames)   PSNR %6.2f dB   SSIM %.4f\n",
              held_out.frames, held_out.psnr, held_out.ssim);
  std::printf("  water region          PSNR %6.2f dB   SSIM %.4f%s\n",
              held_out.psnr_water, held_out.ssim_water,
              scene.has_masks ? "" : "   (no masks)");
  if (has_motion_gt) {
    std::printf("  motion vs truth       EPE %.4g (%.1f%% of mean speed "
                "%.4g) at %d points\n",
                motion.epe, 100 * motion.rel_epe, motion.mean_speed,
                motion.num_points);
  } else {
    std::printf("  motion vs truth       n/a (%s)\n",
                model.motion ? "no gt/ in the scene" : "model has no V");
  }
  std::printf("  loop seam             %.3f (boundary %.4g / within %.4g; "
              "~1 = seamless)\n",
              seam.score, seam.boundary_change, seam.within_change);
  std::printf("  ms per frame          Alg. 1 %.2f  Alg. 2 %.2f  (advect "
              "%.3f vs %.3f, render %.2f)\n",
              timing.alg1_frame_ms(), timing.alg2_frame_ms(),
              timing.alg1_advect_ms, timing.alg2_advect_ms, timing.render_ms);
  std::printf("wrote %s\n", path.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Evaluates a trained looping model.\n"
                    "  es_eval --model DIR --scene DIR --out DIR",
                    Run);
}
