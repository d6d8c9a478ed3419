// Measures a trained looping model: held-out PSNR / SSIM (full image and
// water region), motion error against ground truth when the scene has it,
// realism against the input video (core/metrics/realism.h: detail, motion
// and distribution distance of the Alg. 2 loop seen by every input camera,
// in the water, the static region and the whole frame), the loop-seam
// score of a fixed-view animation, and the per-frame cost of playing it
// with Alg. 1 vs Alg. 2. Writes OUT/eval.json and prints a table. The
// stage is solvers/eval/eval_stage.h.
//
//   es_eval --model DIR --scene DIR --out DIR [--device cpu|cuda]

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "apps/common/image_rasterizer_on.h"
#include "apps/common/loop_frames_on.h"
#include "apps/common/realism_flags.h"
#include "core/base/input_error.h"
#include "solvers/eval/eval_stage.h"

constexpr char kUsage[] =
    "Evaluates a trained looping model.\n"
    "  es_eval --model DIR --scene DIR --out DIR "
    "[--device cpu|cuda]\n"
    "Writes OUT/eval.json (held-out PSNR / SSIM, motion "
    "error vs ground truth, realism, loop seam, render "
    "times) and, for a scene with ground-truth motion, "
    "OUT/motion_gt.csv (V and the truth per water "
    "Gaussian; with --reference_motion also "
    "OUT/motion_gt_reference.csv, that V at the same "
    "points), OUT/held_out/ (each held-out render beside "
    "its input) and OUT/compare/.";

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
DEFINE_bool(held_out_images, true, "Write OUT/held_out/frame_NNNNNN.png: "
            "each held-out frame's render (its composition at its time, "
            "the image the held-out PSNR scores) beside the input.");
DEFINE_double(input_noise, -1,
              "Std (0..1) of the input frames' per-pixel noise, drawn onto "
              "the renders before realism is measured (the input's detail "
              "and frame-to-frame change include its noise, a render's do "
              "not). -1: estimated from consecutive training frames as "
              "es_train --input_noise -1 does (none on clean or 8-bit-only "
              "input); 0: none.");
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

void CheckFlags() {
  es::RequireFlag("model", FLAGS_model);
  es::RequireFlag("scene", FLAGS_scene);
  es::RequireFlag("out", FLAGS_out);
  es::RequirePositive("image_scale", FLAGS_image_scale);
  es::RequireAtLeast("anchor_frame", FLAGS_anchor_frame, -1);
  es::RequireAtLeast("timing_frames", FLAGS_timing_frames, 0);
  es::RequireInRange("input_noise", FLAGS_input_noise, -1, 1);
  if (FLAGS_seam_cycles < 2) {
    throw es::InputError("--seam_cycles must be >= 2 (a boundary needs a "
                         "cycle on each side)");
  }
  if (FLAGS_compare_frames < 0) {
    throw es::InputError("--compare_frames must be >= 0");
  }
}

es::EvalStageOptions OptionsFromFlags() {
  es::EvalStageOptions o;
  o.model_dir = FLAGS_model;
  o.scene_dir = FLAGS_scene;
  o.out_dir = FLAGS_out;
  o.scene.image_scale = FLAGS_image_scale;
  if (FLAGS_white_background) o.render.background.setOnes();
  o.seam_cycles = FLAGS_seam_cycles;
  o.anchor_frame = FLAGS_anchor_frame;
  o.timing_frames = FLAGS_timing_frames;
  o.compare_frames = FLAGS_compare_frames;
  o.held_out_images = FLAGS_held_out_images;
  o.realism_breakdown = FLAGS_realism_breakdown;
  o.reference_motion = FLAGS_reference_motion;
  o.realism = es::RealismOptionsFromFlags();
  o.input_noise = FLAGS_input_noise;
  o.device = FLAGS_device;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, [] {
    CheckFlags();
    es::EvalStageOptions o = OptionsFromFlags();
    const es::ComputeDevice device = es::ParseDeviceFlag(
        FLAGS_device, &o.device_description);
    es::RunEvalStage(o, es::LoopFramesOn(device),
                     es::ImageRasterizerOn(device));
    return 0;
  });
}
