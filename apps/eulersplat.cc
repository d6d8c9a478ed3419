// The all-in-one driver: from a video (or a scene directory) to a looping
// 4D model, a looping video, metrics and a contact sheet. Runs the stage
// binaries that sit next to it (es_poses, es_masks, es_static, es_flowinit,
// es_train, es_animate, es_export, es_eval), each a process of its own so
// every stage can also be run, resumed or debugged alone with the very
// same flags the driver prints.
//
//   eulersplat --video FILE --out DIR [--preset auto|quick|paper]
//   eulersplat --scene DIR --out DIR [--preset auto|quick|paper]
//              [--device cpu|cuda] [--ranks N]
//   eulersplat --scenes A,B,C --out DIR [--ranks N] [--groups G]
//              (a batch: each scene on a group of the ranks, into
//              OUT/<name>; apps/common/driver_batch.h)
//
// OUT/scene/           the frames of --video, or a view of --scene that
//                      adds what it lacks (poses, masks) without writing
//                      into it (solvers/pipeline/scene_inputs.h)
// OUT/masks_sheet.png  auto masks: the frames with their water, to check
// OUT/static/          Stage 1 (static.ply) and Stage 2 (motion_field.bin);
//                      --static_dir puts them elsewhere (shared ablations)
// OUT/model/           Stage 3, the looping model (es_train)
// OUT/animate/         looping video along the input trajectory, with tracks
// OUT/animate_fixed/   fixed-view video and its x-t slice
// OUT/web/             web page that plays the loop (es_export)
// OUT/frame_0.ply      loop frame 0 as a standard 3DGS PLY
// OUT/eval/eval.json   metrics (es_eval)
// OUT/plots/           training plots: loss by term, held-out PSNR vs wall
//                      time, Gaussians (es_plot on each history.csv)
// OUT/contact_sheet.png  frames of both videos and the main plots
// OUT/timings.json     wall and CPU seconds of every stage, the preset
//
// A stage whose outputs exist is skipped (delete its folder to redo it);
// interrupted training resumes from its checkpoint. The flags are in
// apps/common/driver_flags.cc, the plan in solvers/pipeline
// (PipelineController runs it, StagePlan says which binary runs with which
// flags, preset.h holds the presets).

#include "apps/common/app_main.h"
#include "apps/common/driver_flags.h"
#include "solvers/pipeline/pipeline_controller.h"

namespace {

int Main() {
  if (es::SceneBatchAsked())
    return es::RunSceneBatch(es::SceneBatchOptionsFromFlags()) > 0 ? 1 : 0;
  es::PipelineController(es::DriverOptionsFromFlags()).Run();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Runs every stage: video -> poses -> masks -> static -> "
                    "flow init -> joint -> animate -> export -> eval -> "
                    "plots.\n"
                    "  eulersplat --video FILE --out DIR [--preset "
                    "auto|quick|paper] [--device cpu|cuda]\n"
                    "  eulersplat --scene DIR --out DIR [--preset "
                    "auto|quick|paper] [--device cpu|cuda]\n"
                    "  ... --ranks N: es_static, es_flowinit and es_train "
                    "on N MPI ranks (mpiexec)\n"
                    "  eulersplat --scenes A,B,C --out DIR [--ranks N] "
                    "[--groups G]: a batch, each scene on a group of the "
                    "ranks, into OUT/<name>\n"
                    "Writes OUT/static, OUT/model, OUT/animate, "
                    "OUT/animate_fixed, OUT/eval, OUT/plots and "
                    "OUT/contact_sheet.png; a stage whose outputs exist is "
                    "skipped.",
                    Main);
}
