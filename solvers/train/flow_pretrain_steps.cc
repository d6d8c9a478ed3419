#include "solvers/train/flow_pretrain_steps.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/base/lr_schedule.h"
#include "solvers/train/divergence_guard.h"

namespace es {

FlowPretrainOptions StartPretraining(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, FlowPretrainReport* report) {
  CHECK_GE(options.iterations, 0);
  CHECK_GT(options.batch_size, 0);
  if (samples.empty()) {
    throw InputError("no scene-flow samples to pretrain the motion field on");
  }
  report->num_samples = static_cast<int>(samples.size());
  double target_sq = 0;
  for (const SceneFlowSample& s : samples) target_sq += s.v.squaredNorm();
  report->target_rms = std::sqrt(target_sq / samples.size());
  FlowPretrainOptions fit = options;
  fit.tv_weight = options.tv_weight * target_sq / samples.size();
  return fit;
}

PretrainBatches::PretrainBatches(uint32_t seed, int num_samples,
                                 int batch_size)
    : rng_(seed),
      pick_(0, num_samples - 1),
      indices_(std::min(batch_size, num_samples)) {
  CHECK_GT(num_samples, 0);
}

const std::vector<int>& PretrainBatches::Next() {
  for (int& i : indices_) i = pick_(rng_);
  return indices_;
}

AdamOptions PretrainAdamOptions(const FlowPretrainOptions& options) {
  AdamOptions adam;
  adam.eps = options.adam_eps;
  return adam;
}

double PretrainLrDecay(const FlowPretrainOptions& options, int iteration) {
  return LogLinearLr(1.0, options.final_lr_factor, iteration - 1,
                     options.iterations - 1);
}

void ReportPretrainProgress(const FlowPretrainOptions& options,
                            int iteration, int iterations, double seconds,
                            double loss) {
  if (!options.progress || options.log_every <= 0) return;
  if (iteration % options.log_every == 0 || iteration == iterations) {
    options.progress(iteration, seconds, std::sqrt(2.0 * loss));
  }
}

std::vector<GuardedBlock> PretrainGuardedBlocks(
    const FlowPretrainOptions& options, const MotionField& field) {
  // Triplane features start around 0 or 1 and MLP weights below 1.
  const FieldParams p = field.params();
  return {{"V's triplane", "the triplane learning rate",
           options.lr_triplane_flag, options.lr_triplane,
           RunawayBound(p.triplane, field.triplane().num_params(), 1.0)},
          {"V's MLP", "the MLP learning rate", options.lr_mlp_flag,
           options.lr_mlp,
           RunawayBound(p.mlp, field.mlp().num_params(), 1.0)}};
}

double PretrainLossScale(const FlowPretrainReport& report) {
  const double rmse = std::max(report.initial_rmse, report.target_rms);
  return 0.5 * rmse * rmse;
}

void CheckPretrainedField(bool finite, const FlowPretrainReport& report,
                          const FlowPretrainOptions& options) {
  if (!finite)
    throw TrainingDiverged(
        "V pretraining diverged: the fitted motion field is not finite "
        "(learning rates too high?); no field was written");
  const double scale = std::max(report.initial_rmse, report.target_rms);
  const double limit = std::sqrt(kLossGrowth) * scale;
  if (!(report.fit_rmse > limit)) return;
  const std::string cure =
      options.solver == PretrainSolver::kAdam
          ? "the learning rates are too high (" + options.lr_triplane_flag +
                " " + FormatMagnitude(options.lr_triplane) + ", " +
                options.lr_mlp_flag + " " + FormatMagnitude(options.lr_mlp) +
                "): lower them"
          : "the " + PretrainSolverName(options.solver) +
                " solver ran away: use the adam solver";
  throw TrainingDiverged(
      "V pretraining diverged: the fit RMSE grew from " +
      FormatMagnitude(report.initial_rmse) + " to " +
      FormatMagnitude(report.fit_rmse) + " (limit " + FormatMagnitude(limit) +
      ", " + FormatMagnitude(std::sqrt(kLossGrowth)) +
      " times the larger of that start and the targets' RMS " +
      FormatMagnitude(report.target_rms) + "); " + cure +
      "; no field was written");
}

}  // namespace es
