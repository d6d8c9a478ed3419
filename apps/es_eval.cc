// Measures a trained looping model: held-out PSNR / SSIM (full image and
// water region), motion error against ground truth when the scene has it,
// realism against the input video (core/metrics/realism.h: detail, motion
// and distribution distance of the Alg. 2 loop seen by every input camera,
// in the water, the static region and the whole frame), the loop-seam
// score of a fixed-view animation, and the per-frame cost of playing it
// with Alg. 1 vs Alg. 2. Writes OUT/eval.json and prints a table.
//
//   es_eval --model DIR --scene DIR --out DIR [--device cpu|cuda]

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/eval_report.h"
#include "apps/common/flag_checks.h"
#include "apps/common/image_rasterizer_on.h"
#include "apps/common/loop_frames_on.h"
#include "apps/common/realism_flags.h"
#include "apps/common/scaled_scene.h"
#include "core/base/atomic_file.h"
#include "core/fields/field_io.h"
#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/eval/realism_evaluation.h"

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
DEFINE_int32(compare_frames, 4, "Frames of the realism video written to "
             "OUT/compare/ (rendered left, input right) to look at; 0: "
             "none.");
DEFINE_bool(realism_breakdown, false, "Also measure realism on three "
            "variants of the model, to find where motion and detail are "
            "lost: 'training' (Alg. 1 at each frame's true time and cycle "
            "number: what training fits), 'loop_without_residual' (the "
            "loop moved by V alone) and 'canonical' (no V, no D: the "
            "splats as they are). Written to eval.json's "
            "realism_breakdown; costs three more renders of the video.");
DEFINE_string(reference_motion, "", "Also measure this V (a "
              "motion_field.bin, e.g. Stage 2's STATIC/motion_field.bin) "
              "against the ground truth at the same water Gaussians as the "
              "model's V: whether joint training moved V toward the truth "
              "or away from it. (es_flowinit's flow_metrics.json measures "
              "Stage 2's V at Stage 1's water Gaussians, another set of "
              "points.) Used where the scene has ground-truth motion and "
              "the model a V; its values per point go to "
              "OUT/motion_gt_reference.csv (scripts/motion_speed_scale.py "
              "compares the two files).");
DEFINE_string(device, "cpu",
              "Where the images render: cpu, or cuda (the first NVIDIA GPU; "
              "needs a build with the CUDA backend, -DES_CUDA=ON or AUTO "
              "with the CUDA toolkit installed). On cuda the loop (Alg. 2: "
              "the realism video, its breakdown variants, the loop seam) "
              "plays and renders there, and the held-out frames' and the "
              "'training' breakdown's compositions (Alg. 1) are made on the "
              "CPU and rasterized there. Stay on the CPU: the metrics, the "
              "motion error and the Alg. 1 vs Alg. 2 timing (a CPU "
              "figure). The GPU renders in float with its own kernels, so "
              "its figures can differ from cpu's in the last digits.");

namespace {

// Everything es_eval measures.
struct Evaluation {
  int anchor_frame = 0;
  es::LoopMetrics held_out;
  bool has_motion_gt = false;
  es::MotionGtMetrics motion;
  std::vector<es::MotionGtPoint> motion_points;  // per water Gaussian
  // --reference_motion's V at the same points, when measured.
  std::optional<es::MotionGtMetrics> reference_motion;
  std::vector<es::MotionGtPoint> reference_points;
  es::RealismMetrics realism;
  // --realism_breakdown: (name, figures) per model variant.
  std::vector<std::pair<std::string, es::RealismMetrics>> breakdown;
  es::LoopSeamScore seam;
  es::AnimationTiming timing;
};

void CheckFlags() {
  es::RequireFlag("model", FLAGS_model);
  es::RequireFlag("scene", FLAGS_scene);
  es::RequireFlag("out", FLAGS_out);
  es::RequirePositive("image_scale", FLAGS_image_scale);
  es::RequireAtLeast("anchor_frame", FLAGS_anchor_frame, -1);
  es::RequireAtLeast("timing_frames", FLAGS_timing_frames, 0);
  if (FLAGS_seam_cycles < 2) {
    throw es::InputError("--seam_cycles must be >= 2 (a boundary needs a "
                         "cycle on each side)");
  }
  if (FLAGS_compare_frames < 0) {
    throw es::InputError("--compare_frames must be >= 0");
  }
}

int AnchorFrame(const es::Scene& scene) {
  const int anchor =
      FLAGS_anchor_frame >= 0 ? FLAGS_anchor_frame : scene.test[0];
  if (anchor >= static_cast<int>(scene.frames.size())) {
    throw es::InputError("--anchor_frame " + std::to_string(anchor) +
                         " is past the scene's last frame");
  }
  return anchor;
}

// Prints "[eval k/4] what" with the seconds since `start`: the steps differ
// too much in cost for an ETA to mean anything.
void Step(int k, const char* what,
          std::chrono::steady_clock::time_point start) {
  std::printf("[eval %d/4] %s (%.1f s so far)\n", k, what,
              std::chrono::duration<double>(
                  std::chrono::steady_clock::now() - start)
                  .count());
  std::fflush(stdout);
}

Evaluation Evaluate(const es::LoopModel& model,
                    const std::optional<es::MotionField>& reference_motion,
                    const es::Scene& scene, const es::RenderOptions& options,
                    const es::RealismOptions& realism,
                    es::ComputeDevice device) {
  const auto start = std::chrono::steady_clock::now();
  Evaluation e;
  e.anchor_frame = AnchorFrame(scene);
  const es::Camera& anchor = scene.frames[e.anchor_frame].camera;
  // The loop of a model (which must outlive it) on the chosen device.
  const auto loop = [&](const es::LoopModel& m) {
    return es::LoopFramesOn(device, &m, options);
  };
  const std::unique_ptr<es::ImageRasterizer> rasterizer =
      es::ImageRasterizerOn(device, options);
  Step(1, "held-out frames and motion", start);
  e.held_out = es::EvaluateLoopModel(model, scene.frames, scene.test,
                                     rasterizer.get());
  e.has_motion_gt = es::HasMotionGt(FLAGS_scene) && model.motion;
  if (e.has_motion_gt) {
    std::vector<Eigen::Vector3d> points;
    for (int i : model.dynamic_index) {
      points.emplace_back(&model.gaussians.means[3 * i]);
    }
    const es::VelocityFunction truth = es::LoadMotionGt(FLAGS_scene);
    e.motion_points = es::MotionGtPoints(*model.motion, points, truth);
    e.motion = es::SummarizeMotionGt(e.motion_points);
    if (reference_motion) {
      e.reference_points = es::MotionGtPoints(*reference_motion, points, truth);
      e.reference_motion = es::SummarizeMotionGt(e.reference_points);
    }
  }
  Step(2, ("realism over " + std::to_string(scene.frames.size()) +
           " input frames").c_str(),
       start);
  const std::vector<cv::Mat> rendered =
      es::RenderAtInputCameras(loop(model).get(), scene.frames);
  e.realism = es::EvaluateRealism(rendered, scene.frames, realism);
  if (FLAGS_compare_frames > 0) {
    es::WriteComparisonFrames(rendered, scene.frames, FLAGS_compare_frames,
                              FLAGS_out + "/compare");
  }
  if (FLAGS_realism_breakdown) {
    e.breakdown.emplace_back(
        "training",
        es::EvaluateRealism(
            es::RenderTrainingComposition(model, scene.frames,
                                          rasterizer.get()),
            scene.frames, realism));
    const auto add_loop = [&](const char* name, const es::LoopModel& m) {
      e.breakdown.emplace_back(
          name, es::EvaluateRealism(
                    es::RenderAtInputCameras(loop(m).get(), scene.frames),
                    scene.frames, realism));
    };
    es::LoopModel variant = model;
    variant.residual.reset();
    add_loop("loop_without_residual", variant);
    variant.motion.reset();
    add_loop("canonical", variant);
  }
  Step(3, "loop seam", start);
  e.seam = es::EvaluateLoopSeam(loop(model).get(), model.cycle_length,
                                anchor, FLAGS_seam_cycles);
  Step(4,
       device == es::ComputeDevice::kCuda
           ? "Alg. 1 vs Alg. 2 timing (on the CPU)"
           : "Alg. 1 vs Alg. 2 timing",
       start);
  const int timing_frames =
      FLAGS_timing_frames > 0 ? FLAGS_timing_frames : 2 * model.cycle_length;
  e.timing = es::TimeAnimation(model, anchor, timing_frames, options);
  return e;
}

nlohmann::ordered_json EvalJson(const es::LoopModel& model,
                                const Evaluation& e) {
  nlohmann::ordered_json json = {
      {"model", FLAGS_model},
      {"scene", FLAGS_scene},
      {"device", FLAGS_device},
      {"gaussians", model.gaussians.size()},
      {"dynamic_gaussians", model.num_dynamic()},
      {"cycle_length", model.cycle_length},
      {"held_out", es::HeldOutJson(e.held_out)},
      {"motion_gt", nullptr},
      {"realism", es::RealismJson(e.realism)},
      {"loop_seam",
       {{"anchor_frame", e.anchor_frame},
        {"cycles", FLAGS_seam_cycles},
        {"score", e.seam.score},
        {"boundary_change", e.seam.boundary_change},
        {"within_change", e.seam.within_change}}},
      {"render_time_ms",
       {{"frames", e.timing.frames},
        {"alg1_advect", e.timing.alg1_advect_ms},
        {"alg2_advect", e.timing.alg2_advect_ms},
        {"render", e.timing.render_ms},
        {"alg1_frame", e.timing.alg1_frame_ms()},
        {"alg2_frame", e.timing.alg2_frame_ms()},
        {"alg1_alg2_max_position_difference",
         e.timing.max_position_difference}}}};
  if (!e.breakdown.empty()) {
    nlohmann::ordered_json breakdown;
    for (const auto& [name, r] : e.breakdown) {
      breakdown[name] = es::RealismJson(r);
    }
    json["realism_breakdown"] = breakdown;
  }
  if (e.has_motion_gt) {
    json["motion_gt"] = {{"points", e.motion.num_points},
                         {"epe", e.motion.epe},
                         {"mean_speed", e.motion.mean_speed},
                         {"rel_epe", e.motion.rel_epe},
                         {"speed_ratio", e.motion.speed_ratio}};
    if (e.reference_motion) {
      json["motion_gt"]["reference"] = {
          {"field", FLAGS_reference_motion},
          {"epe", e.reference_motion->epe},
          {"rel_epe", e.reference_motion->rel_epe},
          {"speed_ratio", e.reference_motion->speed_ratio}};
    }
  }
  return json;
}

void PrintSummary(const es::LoopModel& model, const es::Scene& scene,
                  const Evaluation& e) {
  std::printf("%s: %d Gaussians (%d dynamic), L = %d\n",
              FLAGS_model.c_str(), model.gaussians.size(),
              model.num_dynamic(), model.cycle_length);
  es::PrintHeldOutRows(e.held_out, scene.has_masks);
  if (e.has_motion_gt) {
    std::printf("  motion vs truth       EPE %.4g (%.1f%% of mean speed "
                "%.4g, speed ratio %.2f) at %d points\n",
                e.motion.epe, 100 * e.motion.rel_epe, e.motion.mean_speed,
                e.motion.speed_ratio, e.motion.num_points);
    if (e.reference_motion) {
      std::printf("  reference V there     EPE %.4g (%.1f%%, speed ratio "
                  "%.2f): %s\n",
                  e.reference_motion->epe,
                  100 * e.reference_motion->rel_epe,
                  e.reference_motion->speed_ratio,
                  FLAGS_reference_motion.c_str());
    }
  } else {
    std::printf("  motion vs truth       n/a (%s)\n",
                model.motion ? "no gt/ in the scene" : "model has no V");
  }
  std::printf("  realism vs the input (ratios: 1 = like the input; "
              "distance: 0 = same statistics)\n");
  es::PrintRealismRow("  water", e.realism.water);
  es::PrintRealismRow("  static (control)", e.realism.static_region);
  es::PrintRealismRow("  whole frame", e.realism.frame);
  for (const auto& [name, r] : e.breakdown) {
    es::PrintRealismRow(("  water, " + name).c_str(), r.water);
  }
  std::printf("  loop seam             %.3f (boundary %.4g / within %.4g; "
              "~1 = seamless)\n",
              e.seam.score, e.seam.boundary_change, e.seam.within_change);
  std::printf("  ms per frame          Alg. 1 %.2f  Alg. 2 %.2f  (advect "
              "%.3f vs %.3f, render %.2f)\n",
              e.timing.alg1_frame_ms(), e.timing.alg2_frame_ms(),
              e.timing.alg1_advect_ms, e.timing.alg2_advect_ms,
              e.timing.render_ms);
}

int Run() {
  CheckFlags();
  const es::RealismOptions realism = es::RealismOptionsFromFlags();
  std::string device_name;
  const es::ComputeDevice device =
      es::ParseDeviceFlag(FLAGS_device, &device_name);
  es::PrepareOutputDirectory(FLAGS_out, "out");
  es::RenderOptions options;
  if (FLAGS_white_background) options.background.setOnes();
  const es::Scene scene = es::LoadScaledScene(FLAGS_scene, FLAGS_image_scale);
  const es::LoopModel model = es::LoadLoopModel(FLAGS_model);
  std::optional<es::MotionField> reference_motion;
  if (!FLAGS_reference_motion.empty()) {
    reference_motion = es::LoadMotionField(FLAGS_reference_motion);
  }
  if (scene.test.empty()) {
    throw es::InputError(FLAGS_scene + ": no held-out frames to evaluate "
                         "(see split.txt)");
  }
  if (device == es::ComputeDevice::kCuda) {
    std::printf("rendering on %s: the loop (Alg. 2) and the rasterizer; "
                "on the CPU: Alg. 1's compositions, the motion error, the "
                "Alg. 1 vs Alg. 2 timing and every metric\n",
                device_name.c_str());
  }
  const Evaluation e =
      Evaluate(model, reference_motion, scene, options, realism, device);
  const std::string path = FLAGS_out + "/eval.json";
  es::WriteJsonFile(path, EvalJson(model, e));
  PrintSummary(model, scene, e);
  std::printf("wrote %s\n", path.c_str());
  const auto write_points = [](const std::string& name,
                               const std::vector<es::MotionGtPoint>& points,
                               const char* what) {
    const std::string points_path = FLAGS_out + "/" + name;
    es::WriteTextFileAtomically(points_path, es::MotionGtCsv(points));
    std::printf("wrote %s (%s)\n", points_path.c_str(), what);
  };
  if (e.has_motion_gt) {
    write_points("motion_gt.csv", e.motion_points,
                 "V and the true velocity at each water Gaussian");
  }
  if (e.reference_motion) {
    write_points("motion_gt_reference.csv", e.reference_points,
                 "--reference_motion's V at the same points");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Evaluates a trained looping model.\n"
                    "  es_eval --model DIR --scene DIR --out DIR "
                    "[--device cpu|cuda]\n"
                    "Writes OUT/eval.json (held-out PSNR / SSIM, motion "
                    "error vs ground truth, realism, loop seam, render "
                    "times) and, for a scene with ground-truth motion, "
                    "OUT/motion_gt.csv (V and the truth per water "
                    "Gaussian; with --reference_motion also "
                    "OUT/motion_gt_reference.csv, that V at the same "
                    "points).",
                    Run);
}
