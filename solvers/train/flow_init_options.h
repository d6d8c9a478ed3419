#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_OPTIONS_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_OPTIONS_H_

// What Stage 2 (flow_init_stage.h) is asked and what it reports, shared
// with the flow_metrics.json it writes (flow_init_metrics.h).

#include <cstdint>
#include <optional>
#include <string>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "core/io/scene.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/train/flow_pretrain_options.h"

namespace es {

struct FlowInitStageOptions {
  std::string scene_dir;
  std::string static_path;  // Stage 1's model; empty: scene_dir/static.ply
  std::string out_dir;      // empty: scene_dir
  SceneOptions scene;
  // The flow and its lifting. Its progress is the stage's (a line per
  // frame pair), and lifting.line_of_sight_weight counts only with
  // free_line_of_sight.
  SceneFlowOptions flow;
  // false: the samples claim no motion along the line of sight (weight 1
  // whatever flow.lifting.line_of_sight_weight says; for ablations).
  bool free_line_of_sight = true;
  int max_samples = 500000;     // a random subset of at most this many
  uint32_t sample_seed = 1;     // of that subset
  // Diagnosis on synthetic scenes (needs scene_dir/gt/): each kept sample
  // gets this part of the true velocity at its position; none: the flow's.
  std::optional<TruthPart> oracle;
  double dynamic_threshold = 0.2;  // sigmoid(dynamic_logit) above: water
  MotionFieldOptions field;
  // Its progress is the stage's (a line and a flow_history.csv row per log).
  FlowPretrainOptions pretrain;
  bool profile = false;  // print where the time goes after the pretraining
};

// es_flowinit --oracle_velocity's spellings: none (nullopt), seen, full.
// Parse throws InputError naming the flag on others.
std::optional<TruthPart> ParseOracleVelocity(const std::string& name);
std::string OracleVelocityName(const std::optional<TruthPart>& oracle);

struct FlowInitStageResult {
  SceneFlowResult lifted;  // the samples as written (subset, oracle)
  FlowPretrainReport fit;
  int num_dynamic = 0;
  double seconds = 0;  // the whole stage, loading included
  // V and the samples against the scene's ground truth, when it has gt/.
  std::optional<MotionGtMetrics> field_gt, samples_gt;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_OPTIONS_H_
