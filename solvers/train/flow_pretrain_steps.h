#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_STEPS_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_STEPS_H_

// The host-side pieces of Stage 2's V pretraining that the CPU
// (PretrainMotionField, flow_pretrain.h) and the device
// (cuda::PretrainMotionFieldOnDevice) share, so both take the same Adam
// steps: the input checks and the report's start, the mini-batches, the
// learning-rate decay, the progress calls and the final finiteness rule.

#include <chrono>
#include <cstdint>
#include <random>
#include <vector>

#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"
#include "solvers/optim/adam.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_pretrain_options.h"

namespace es {

class PretrainStopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_ =
      std::chrono::steady_clock::now();
};

// Checks the options and samples (InputError when there are none) and
// fills report->num_samples and target_rms. Returns the options the fits
// take: tv_weight in the data term's units (times the mean squared target
// speed).
FlowPretrainOptions StartPretraining(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, FlowPretrainReport* report);

// Adam's mini-batches: min(batch_size, num_samples) indices per step,
// drawn uniformly in sequence from one generator seeded `seed`.
class PretrainBatches {
 public:
  PretrainBatches(uint32_t seed, int num_samples, int batch_size);
  // The next step's batch.
  const std::vector<int>& Next();

 private:
  std::mt19937 rng_;
  std::uniform_int_distribution<int> pick_;
  std::vector<int> indices_;
};

AdamOptions PretrainAdamOptions(const FlowPretrainOptions& options);
// The factor on both learning rates at Adam step `iteration` (from 1):
// 1 at the first, final_lr_factor at the last, log-linear between.
double PretrainLrDecay(const FlowPretrainOptions& options, int iteration);

// Calls options.progress every log_every iterations and at the last, with
// the RMSE of a batch whose loss (mean 0.5 |r|^2) is `loss`.
void ReportPretrainProgress(const FlowPretrainOptions& options,
                            int iteration, int iterations, double seconds,
                            double loss);

// V's two blocks (triplane, MLP) as Adam's DivergenceGuard watches them,
// bounded by their values in `field`, the field the fit starts from.
std::vector<GuardedBlock> PretrainGuardedBlocks(
    const FlowPretrainOptions& options, const MotionField& field);
// The scale of Adam's loss (mean 0.5 |r|^2) for DivergenceGuard::CheckLoss:
// that of the larger of the starting RMSE and the targets' RMS.
double PretrainLossScale(const FlowPretrainReport& report);

// Throws TrainingDiverged unless the fitted field's parameters and its
// fit RMSE are finite, and unless that RMSE is within sqrt(kLossGrowth)
// times the larger of the starting RMSE and the targets' RMS: whatever the
// solver, a non-finite or runaway field is never handed on to be written.
void CheckPretrainedField(bool finite, const FlowPretrainReport& report,
                          const FlowPretrainOptions& options);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_STEPS_H_
