#ifndef EULERSPLAT_SOLVERS_EVAL_EVAL_OPTIONS_H_
#define EULERSPLAT_SOLVERS_EVAL_EVAL_OPTIONS_H_

// What es_eval's stage (eval_stage.h) is asked and what it measures,
// shared with the eval.json and the table it writes (eval_report.h).

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/io/scene.h"
#include "core/metrics/loop_seam.h"
#include "core/metrics/realism.h"
#include "core/render/rasterizer.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/eval/training_water_psnr.h"

namespace es {

struct EvalStageOptions {
  std::string model_dir;  // a trained looping model (es_train --out)
  std::string scene_dir;  // the scene it was trained on
  std::string out_dir;    // eval.json, motion_gt*.csv, compare/ (created)
  SceneOptions scene;
  RenderOptions render;   // the background the model was trained on
  int seam_cycles = 3;    // loops of the fixed view the seam is scored on
  int anchor_frame = -1;  // camera of the fixed view; -1: first held-out
  int timing_frames = 0;  // frames timed for Alg. 1 vs Alg. 2; 0: 2 L
  int compare_frames = 4;  // realism frames written to out_dir/compare/
  // Every held-out frame's render (Alg. 1 at its time) beside the input,
  // written to out_dir/held_out/: the images the held-out PSNR scores.
  bool held_out_images = true;
  // Also the realism of three variants of the model: "training" (Alg. 1
  // at each frame's time and cycle number), "loop_without_residual" and
  // "canonical" (no V, no D).
  bool realism_breakdown = false;
  // A motion_field.bin also measured against the ground truth at the
  // model's water Gaussians; empty: none.
  std::string reference_motion;
  RealismOptions realism;
  // The input's per-pixel noise drawn onto the renders before realism is
  // measured (costs/water_input_noise.h): < 0 estimated from the
  // training frames, as es_train's --input_noise -1; >= 0 this std on
  // every opponent channel (0: none).
  double input_noise = -1;
  // Where the images render, as eval.json records it (--device: cpu or
  // cuda); off the CPU, device_description is printed with what runs where.
  std::string device = "cpu";
  std::string device_description;
};

// Everything the stage measures.
struct EvalStageResult {
  int anchor_frame = 0;
  LoopMetrics held_out;
  bool has_motion_gt = false;
  MotionGtMetrics motion;
  std::vector<MotionGtPoint> motion_points;  // per water Gaussian
  // The reference motion's V at the same points, when measured.
  std::optional<MotionGtMetrics> reference_motion;
  std::vector<MotionGtPoint> reference_points;
  RealismMetrics realism;
  std::array<double, 3> input_noise = {0, 0, 0};  // drawn for realism
  // realism_breakdown: (name, figures) per model variant.
  std::vector<std::pair<std::string, RealismMetrics>> breakdown;
  LoopSeamScore seam;
  AnimationTiming timing;
  // Stage 1's and Stage 3's first and last water PSNR, as training
  // recorded them.
  TrainingWaterPsnr training;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_EVAL_OPTIONS_H_
