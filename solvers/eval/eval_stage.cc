#include "solvers/eval/eval_stage.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/fields/field_io.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "costs/water_input_noise.h"
#include "solvers/eval/eval_report.h"
#include "solvers/eval/realism_evaluation.h"

namespace es {
namespace {

int AnchorFrame(const Scene& scene, int anchor_frame) {
  const int anchor = anchor_frame >= 0 ? anchor_frame : scene.test[0];
  if (anchor >= static_cast<int>(scene.frames.size())) {
    throw InputError("--anchor_frame " + std::to_string(anchor) +
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

// The noise drawn onto the renders for realism: `sigma` on every channel,
// or for sigma < 0 as es_train estimates it.
std::array<double, 3> RealismInputNoise(const Scene& scene, double sigma) {
  if (sigma >= 0) return {sigma, sigma, sigma};
  return EstimateInputNoise(scene.frames, scene.train);
}

}  // namespace

EvalStageResult EvaluateLoopStage(
    const LoopModel& model, const std::optional<MotionField>& reference,
    const Scene& scene, const EvalStageOptions& o,
    const LoopFramesFactory& make_frames,
    const ImageRasterizerFactory& make_rasterizer) {
  const auto start = std::chrono::steady_clock::now();
  EvalStageResult e;
  e.anchor_frame = AnchorFrame(scene, o.anchor_frame);
  const Camera& anchor = scene.frames[e.anchor_frame].camera;
  // The loop of a model (which must outlive it) on the chosen device.
  const auto loop = [&](const LoopModel& m) {
    return make_frames(&m, o.render);
  };
  const std::unique_ptr<ImageRasterizer> rasterizer =
      make_rasterizer(o.render);
  Step(1, "held-out frames and motion", start);
  const std::vector<cv::Mat> held_out = RenderCompositions(
      model, scene.frames, scene.test, rasterizer.get());
  e.held_out = CompareWithFrames(held_out, scene.frames, scene.test);
  if (o.held_out_images) {
    WriteSideBySideFrames(held_out, scene.frames, scene.test,
                          o.out_dir + "/held_out");
  }
  e.has_motion_gt = HasMotionGt(o.scene_dir) && model.motion;
  if (e.has_motion_gt) {
    std::vector<Eigen::Vector3d> points;
    for (int i : model.dynamic_index) {
      points.emplace_back(&model.gaussians.means[3 * i]);
    }
    const VelocityFunction truth = LoadMotionGt(o.scene_dir);
    e.motion_points = MotionGtPoints(*model.motion, points, truth);
    e.motion = SummarizeMotionGt(e.motion_points);
    if (reference) {
      e.reference_points = MotionGtPoints(*reference, points, truth);
      e.reference_motion = SummarizeMotionGt(e.reference_points);
    }
  }
  Step(2, ("realism over " + std::to_string(scene.frames.size()) +
           " input frames").c_str(),
       start);
  const std::vector<cv::Mat> rendered =
      RenderAtInputCameras(loop(model).get(), scene.frames);
  e.input_noise = RealismInputNoise(scene, o.input_noise);
  e.realism = EvaluateRealism(rendered, scene.frames, o.realism, e.input_noise);
  if (o.compare_frames > 0) {
    WriteComparisonFrames(rendered, scene.frames, o.compare_frames,
                          o.out_dir + "/compare");
  }
  if (o.realism_breakdown) {
    e.breakdown.emplace_back(
        "training",
        EvaluateRealism(RenderTrainingComposition(model, scene.frames,
                                                  rasterizer.get()),
                        scene.frames, o.realism, e.input_noise));
    const auto add_loop = [&](const char* name, const LoopModel& m) {
      e.breakdown.emplace_back(
          name, EvaluateRealism(
                    RenderAtInputCameras(loop(m).get(), scene.frames),
                    scene.frames, o.realism, e.input_noise));
    };
    LoopModel variant = model;
    variant.residual.reset();
    add_loop("loop_without_residual", variant);
    variant.motion.reset();
    add_loop("canonical", variant);
  }
  Step(3, "loop seam", start);
  e.seam = EvaluateLoopSeam(loop(model).get(), model.cycle_length, anchor,
                            o.seam_cycles);
  Step(4,
       o.device != "cpu" ? "Alg. 1 vs Alg. 2 timing (on the CPU)"
                         : "Alg. 1 vs Alg. 2 timing",
       start);
  const int timing_frames =
      o.timing_frames > 0 ? o.timing_frames : 2 * model.cycle_length;
  e.timing = TimeAnimation(model, anchor, timing_frames, o.render);
  return e;
}

EvalStageResult RunEvalStage(const EvalStageOptions& o,
                             const LoopFramesFactory& make_frames,
                             const ImageRasterizerFactory& make_rasterizer) {
  PrepareOutputDirectory(o.out_dir, "out");
  const Scene scene = LoadScene(o.scene_dir, o.scene);
  const LoopModel model = LoadLoopModel(o.model_dir);
  std::optional<MotionField> reference;
  if (!o.reference_motion.empty()) {
    reference = LoadMotionField(o.reference_motion);
  }
  if (scene.test.empty()) {
    throw InputError(o.scene_dir + ": no held-out frames to evaluate "
                     "(see split.txt)");
  }
  if (o.device != "cpu") {
    std::printf("rendering on %s: the loop (Alg. 2) and the rasterizer; "
                "on the CPU: Alg. 1's compositions, the motion error, the "
                "Alg. 1 vs Alg. 2 timing and every metric\n",
                o.device_description.c_str());
  }
  EvalStageResult e = EvaluateLoopStage(model, reference, scene, o,
                                        make_frames, make_rasterizer);
  e.training = ReadTrainingWaterPsnr(o.model_dir);
  const std::string path = o.out_dir + "/eval.json";
  WriteJsonFile(path, EvalJson(o, model, e));
  PrintEvalSummary(o, model, scene, e);
  std::printf("wrote %s\n", path.c_str());
  const auto write_points = [&o](const std::string& name,
                                 const std::vector<MotionGtPoint>& points,
                                 const char* what) {
    const std::string points_path = o.out_dir + "/" + name;
    WriteTextFileAtomically(points_path, MotionGtCsv(points));
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
  return e;
}

}  // namespace es
