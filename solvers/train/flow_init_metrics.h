#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_METRICS_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_METRICS_H_

#include <string>

#include <nlohmann/json.hpp>

#include "solvers/train/flow_init_options.h"

namespace es {

// Stage 2's flow_metrics.json: the fit, the lifting's counts and timings,
// the options that shaped them (as their flags spell them), and the
// ground-truth errors when the result has them.
nlohmann::ordered_json FlowMetricsJson(const FlowInitStageOptions& options,
                                       const FlowInitStageResult& result);
// Writes it to `path` (atomically).
void WriteFlowMetrics(const std::string& path,
                      const FlowInitStageOptions& options,
                      const FlowInitStageResult& result);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_INIT_METRICS_H_
