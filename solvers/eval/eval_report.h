#ifndef EULERSPLAT_SOLVERS_EVAL_EVAL_REPORT_H_
#define EULERSPLAT_SOLVERS_EVAL_EVAL_REPORT_H_

#include <nlohmann/json.hpp>

#include "core/io/scene.h"
#include "core/loop/loop_model.h"
#include "core/metrics/realism.h"
#include "solvers/eval/eval_options.h"
#include "solvers/eval/loop_evaluation.h"

namespace es {

// How es_eval and es_compare write and print held-out and realism
// figures, so their JSON files and tables read the same.
nlohmann::ordered_json HeldOutJson(const LoopMetrics& metrics);
// The held-out and water-region PSNR / SSIM rows of the table; with
// `stage1_far_scenery` (finite) Stage 1's far-scenery PSNR beside the
// model's.
void PrintHeldOutRows(const LoopMetrics& metrics, bool has_masks,
                      double stage1_far_scenery = NAN);
nlohmann::ordered_json RealismRegionJson(const RealismRegion& region);
// {"water", "static", "frame"} of RealismRegionJson.
nlohmann::ordered_json RealismJson(const RealismMetrics& metrics);
// One table row: "  <name> detail .. motion .. distance 2D .. 3D ..".
void PrintRealismRow(const char* name, const RealismRegion& region);

// es_eval's eval.json: the model, what was measured and how.
nlohmann::ordered_json EvalJson(const EvalStageOptions& options,
                                const LoopModel& model,
                                const EvalStageResult& result);
// es_eval's table of the same figures.
void PrintEvalSummary(const EvalStageOptions& options, const LoopModel& model,
                      const Scene& scene, const EvalStageResult& result);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_EVAL_EVAL_REPORT_H_
