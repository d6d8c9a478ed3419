#ifndef EULERSPLAT_SOLVERS_EVAL_EVAL_STAGE_H_
#define EULERSPLAT_SOLVERS_EVAL_EVAL_STAGE_H_

// es_eval's stage: a trained looping model measured on its scene.

#include <optional>

#include "core/fields/motion_field.h"
#include "core/io/scene.h"
#include "core/loop/loop_frames_factory.h"
#include "core/loop/loop_model.h"
#include "core/render/image_rasterizer_factory.h"
#include "solvers/eval/eval_options.h"

namespace es {

// Measures `model` on `scene` (which must have held-out frames), printing
// "[eval k/4] ..." before each step: held-out PSNR / SSIM (Alg. 1's
// compositions rendered by `make_rasterizer`'s rasterizer), the motion
// error against the scene's ground truth (and the reference's, when
// given), realism of the loop (played by `make_frames`) at every input
// camera (writing options.compare_frames of it to out_dir/compare/), the
// breakdown when asked, the loop seam of the fixed view and the Alg. 1 vs
// Alg. 2 timing (on the CPU). Throws InputError for an anchor frame past
// the scene's last.
EvalStageResult EvaluateLoopStage(
    const LoopModel& model, const std::optional<MotionField>& reference,
    const Scene& scene, const EvalStageOptions& options,
    const LoopFramesFactory& make_frames,
    const ImageRasterizerFactory& make_rasterizer);

// es_eval: checks out_dir for writing, loads the scene, the model and the
// reference motion, measures them (EvaluateLoopStage) and writes
// out_dir/eval.json, prints the table, and for a scene with ground-truth
// motion writes out_dir/motion_gt.csv (and motion_gt_reference.csv with a
// reference). Throws InputError for a scene without held-out frames and
// for unreadable inputs. The factories pick the device.
EvalStageResult RunEvalStage(
    const EvalStageOptions& options,
    const LoopFramesFactory& make_frames = MakeCpuLoopFrames,
    const ImageRasterizerFactory& make_rasterizer = MakeCpuImageRasterizer);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_EVAL_STAGE_H_
