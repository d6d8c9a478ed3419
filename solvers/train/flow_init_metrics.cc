#include "solvers/train/flow_init_metrics.h"

#include "core/io/json_file.h"

namespace es {

nlohmann::ordered_json FlowMetricsJson(const FlowInitStageOptions& o,
                                       const FlowInitStageResult& r) {
  const FlowPretrainReport& fit = r.fit;
  const SceneFlowResult& lifted = r.lifted;
  const LiftingStats& s = lifted.stats;
  nlohmann::ordered_json json = {
      {"num_samples", fit.num_samples},
      {"seconds", r.seconds},
      {"fit_rmse", fit.fit_rmse},
      {"target_rms", fit.target_rms},
      {"initial_rmse", fit.initial_rmse},
      {"flow", FlowMethodName(o.flow.method)},
      {"flow_image", FlowImageName(o.flow.image)},
      {"second_end", SecondEndName(o.flow.lifting.second_end)},
      {"frame_gap", o.flow.lifting.frame_gap},
      {"free_line_of_sight", o.free_line_of_sight},
      {"line_of_sight_weight", o.flow.lifting.line_of_sight_weight},
      {"tv_weight", o.pretrain.tv_weight},
      {"oracle_velocity", OracleVelocityName(o.oracle)},
      {"solver", PretrainSolverName(o.pretrain.solver)},
      {"iterations", fit.iterations},
      {"num_pairs", lifted.num_pairs},
      {"num_dynamic", r.num_dynamic},
      {"water_from_masks", lifted.used_masks},
      {"candidates", s.candidates},
      {"rejected_no_depth", s.no_depth},
      {"rejected_depth_edge", s.depth_edge},
      {"rejected_outside", s.outside},
      {"rejected_inconsistent", s.inconsistent},
      {"rejected_not_water", s.not_water},
      {"render_seconds", lifted.render_seconds},
      {"flow_seconds", lifted.flow_seconds},
      {"lift_seconds", lifted.lift_seconds},
      {"pretrain_seconds", fit.seconds}};
  if (r.field_gt && r.samples_gt) {
    json["epe_gt"] = r.field_gt->epe;
    json["rel_epe_gt"] = r.field_gt->rel_epe;
    json["mean_speed_gt"] = r.field_gt->mean_speed;
    json["speed_ratio_gt"] = r.field_gt->speed_ratio;
    json["samples_rel_epe_gt"] = r.samples_gt->rel_epe;
    json["samples_speed_ratio_gt"] = r.samples_gt->speed_ratio;
  }
  return json;
}

void WriteFlowMetrics(const std::string& path, const FlowInitStageOptions& o,
                      const FlowInitStageResult& r) {
  WriteJsonFile(path, FlowMetricsJson(o, r));
}

}  // namespace es
