#ifndef EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_OPTIONS_H_
#define EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_OPTIONS_H_

// What Stage 2's V pretraining is asked and what it reports, shared by the
// CPU fit (flow_pretrain.h), its device twin and the steps both take
// (flow_pretrain_steps.h).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/base/communicator.h"
#include "core/fields/motion_field.h"
#include "core/flow/flow_lifting.h"

namespace es {

// How V is fitted to the lifted scene-flow samples (Stage 2).
enum class PretrainSolver {
  kAdam,   // Adam on random mini-batches (default, scales to any field)
  kLbfgs,  // ceres::GradientProblemSolver (LBFGS) on a fixed sample subset
  kLm,     // Levenberg-Marquardt on one fixed mini-batch: Ceres stores the
           // Jacobian densely (3 B x num_params), so small fields only
};

// Flag spellings adam, lbfgs, lm; Parse throws InputError on others.
std::string PretrainSolverName(PretrainSolver solver);
PretrainSolver ParsePretrainSolver(const std::string& name);

struct FlowPretrainOptions {
  PretrainSolver solver = PretrainSolver::kAdam;
  int iterations = 2000;      // Adam steps / LBFGS or LM iterations
  int batch_size = 8192;      // Adam's mini-batch; LM's fixed batch
  // Adam learning rates, decayed log-linearly to final_lr_factor times
  // these by the last step. V's output is scaled by the box (see
  // MotionFieldOptions), so they do not depend on the scene's units.
  double lr_triplane = 1e-2;
  double lr_mlp = 1e-3;
  // What sets those two, for a divergence message (es_flowinit's flags).
  std::string lr_triplane_flag = "--lr_triplane";
  std::string lr_mlp_flag = "--lr_mlp";
  double final_lr_factor = 0.1;
  double adam_eps = 1e-15;
  // Total variation on the planes (Triplane::TotalVariation), Adam and
  // LBFGS: texels no sample touches follow their neighbours instead of
  // keeping their initial noise, so V extrapolates smoothly to water the
  // flow did not reach. Relative to the mean squared target speed, so the
  // balance with the data term does not depend on the scene's units or
  // speeds.
  double tv_weight = 1.0;
  int lbfgs_max_samples = 200000;  // LBFGS evaluates all of these per step
  // LM refuses problems whose dense Jacobian exceeds this many values.
  int64_t lm_max_jacobian_values = 50000000;
  uint32_t seed = 0;
  // Adam: this many non-finite steps in a row stop the fit
  // (DivergenceGuard), as do a block growing kRunawayGrowth times its
  // initial scale and a loss growing kLossGrowth times its; every solver
  // throws TrainingDiverged rather than return a non-finite field or one
  // whose fit RMSE grew by orders of magnitude.
  int max_nonfinite_steps = 10;
  // Data-parallel Adam: each mini-batch is cut into `shards` runs of
  // samples, shard k evaluated on rank k mod comm->size(), and their
  // gradients, weighted by their share of the batch, summed over the ranks
  // (solvers/train/data_parallel.h). 0: one shard per rank. The fit depends
  // on the shards, not on the ranks: 2 ranks give bit for bit what one
  // process gives with 2 shards (more ranks: to reassociation). Null comm:
  // one process. The other solvers run in one process only.
  Communicator* comm = nullptr;
  int shards = 0;
  // Called every log_every iterations (and at the end) with the iteration,
  // the seconds so far and the RMSE on the current batch / subset.
  int log_every = 100;
  std::function<void(int, double, double)> progress;
};

struct FlowPretrainReport {
  int num_samples = 0;
  int iterations = 0;
  double seconds = 0;
  double initial_rmse = 0;  // sqrt(mean |V(x) - V'(x)|^2) over all samples
  double fit_rmse = 0;
  double target_rms = 0;    // sqrt(mean |V'(x)|^2): the scale to compare to
};

// What fits V: PretrainMotionField, or its device twin
// (cuda::PretrainMotionFieldOnDevice); apps pick one by --device.
using FlowPretrainer = FlowPretrainReport (*)(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, MotionField* field);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_FLOW_PRETRAIN_OPTIONS_H_
