#include "solvers/train/flow_pretrain.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>

#include <ceres/ceres.h>
#include <glog/logging.h>

#include "core/base/input_error.h"
#include "core/base/stage_profile.h"
#include "costs/scene_flow_cost.h"
#include "solvers/optim/adam.h"
#include "solvers/train/data_parallel.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_pretrain_steps.h"

namespace es {
namespace {

// k distinct indices out of n (all of them when k >= n).
std::vector<int> RandomSubset(int n, int k, std::mt19937* rng) {
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  if (k >= n) return all;
  std::shuffle(all.begin(), all.end(), *rng);
  all.resize(k);
  return all;
}

// One Adam mini-batch's loss and gradient, the batch cut into shards
// spread over the ranks (FlowPretrainOptions::shards): each shard's mean
// loss and gradient weighted by its share of the batch, summed in shard
// order on each rank, then over the ranks.
class ShardedSceneFlowLoss {
 public:
  ShardedSceneFlowLoss(const MotionField* field,
                       const FlowPretrainOptions& options)
      : field_(field),
        cost_(field, &shard_),
        comm_(options.comm != nullptr ? options.comm : &SingleProcess()),
        shards_(options.shards > 0 ? options.shards : comm_->size()),
        sizes_{static_cast<size_t>(field->triplane().num_params()),
               static_cast<size_t>(field->mlp().num_params()), 1},
        grad_tri_(sizes_[0]),
        grad_mlp_(sizes_[1]) {
    CheckBatchFrames(shards_, *comm_, "--batch_shards");
  }

  // The loss; its gradient into g_tri and g_mlp (overwritten).
  double Evaluate(const std::vector<SceneFlowSample>& samples,
                  const std::vector<int>& batch, double* g_tri,
                  double* g_mlp) {
    if (shards_ == 1) {  // one process, the batch whole
      shard_.Assign(samples, batch);
      std::fill_n(g_tri, sizes_[0], 0.0);
      std::fill_n(g_mlp, sizes_[1], 0.0);
      return cost_.Loss(field_->params(), {g_tri, g_mlp});
    }
    sum_.Reset(sizes_);
    const size_t n = batch.size();
    for (int k = 0; k < shards_; ++k) {
      if (!RendersBatchFrame(*comm_, k)) continue;
      const size_t begin = n * k / shards_, end = n * (k + 1) / shards_;
      if (end == begin) continue;
      shard_indices_.assign(batch.begin() + begin, batch.begin() + end);
      shard_.Assign(samples, shard_indices_);
      std::fill(grad_tri_.begin(), grad_tri_.end(), 0.0);
      std::fill(grad_mlp_.begin(), grad_mlp_.end(), 0.0);
      const double weight = static_cast<double>(end - begin) / n;
      double loss =
          weight * cost_.Loss(field_->params(),
                              {grad_tri_.data(), grad_mlp_.data()});
      for (double& g : grad_tri_) g *= weight;
      for (double& g : grad_mlp_) g *= weight;
      sum_.Add(0, grad_tri_.data());
      sum_.Add(1, grad_mlp_.data());
      sum_.Add(2, &loss);
    }
    sum_.AllreduceSum(comm_);
    std::copy_n(sum_.at(0), sizes_[0], g_tri);
    std::copy_n(sum_.at(1), sizes_[1], g_mlp);
    return sum_.at(2)[0];
  }

 private:
  const MotionField* field_;
  SceneFlowBatch shard_;
  const SceneFlowCost cost_;
  Communicator* comm_;
  int shards_;
  std::vector<size_t> sizes_;
  std::vector<double> grad_tri_, grad_mlp_;
  std::vector<int> shard_indices_;
  PackedSum sum_;
};

// `loss_scale`: PretrainLossScale.
int FitWithAdam(const std::vector<SceneFlowSample>& samples,
                const FlowPretrainOptions& options,
                const PretrainStopwatch& clock, double loss_scale,
                MotionField* field) {
  const int n_tri = field->triplane().num_params();
  const int n_mlp = field->mlp().num_params();
  std::vector<double> g_tri(n_tri), m_tri(n_tri, 0.0), v_tri(n_tri, 0.0);
  std::vector<double> g_mlp(n_mlp), m_mlp(n_mlp, 0.0), v_mlp(n_mlp, 0.0);
  ShardedSceneFlowLoss cost(field, options);
  PretrainBatches batches(options.seed, static_cast<int>(samples.size()),
                          options.batch_size);
  const AdamOptions adam = PretrainAdamOptions(options);
  DivergenceGuard guard("V pretraining", options.max_nonfinite_steps,
                        "no field was written");
  const std::vector<GuardedBlock> blocks =
      PretrainGuardedBlocks(options, *field);
  for (int it = 1; it <= options.iterations; ++it) {
    ScopedStage timer(Stage::kIteration);
    const double loss = cost.Evaluate(samples, batches.Next(), g_tri.data(),
                                      g_mlp.data());
    // Added after the sum: a term of the step, not of a shard.
    if (options.tv_weight > 0) {
      field->triplane().TotalVariation(field->triplane_params().data(),
                                       options.tv_weight, g_tri.data());
    }
    if (!guard.Accept(it, std::isfinite(loss) && AllFinite(g_tri) &&
                              AllFinite(g_mlp)))
      continue;
    guard.CheckLoss(it, loss, loss_scale, blocks);
    const double decay = PretrainLrDecay(options, it);
    AdamUpdate(adam, it, options.lr_triplane * decay, n_tri, g_tri.data(),
               m_tri.data(), v_tri.data(), field->triplane_params().data());
    AdamUpdate(adam, it, options.lr_mlp * decay, n_mlp, g_mlp.data(),
               m_mlp.data(), v_mlp.data(), field->mlp_params().data());
    guard.CheckBlocks(it, blocks,
                      {MaxMagnitude(field->triplane_params()),
                       MaxMagnitude(field->mlp_params())});
    ReportPretrainProgress(options, it, options.iterations, clock.seconds(),
                           loss);
  }
  return options.iterations;
}

// The pretraining loss over V's concatenated parameters [triplane | MLP],
// for ceres::GradientProblemSolver.
class SceneFlowObjective : public ceres::FirstOrderFunction {
 public:
  SceneFlowObjective(const MotionField* field, const SceneFlowBatch* batch,
                     double tv_weight)
      : field_(field), cost_(field, batch), tv_weight_(tv_weight),
        n_tri_(field->triplane().num_params()),
        n_mlp_(field->mlp().num_params()) {}

  bool Evaluate(const double* parameters, double* cost,
                double* gradient) const override {
    const FieldParams params{parameters, parameters + n_tri_};
    FieldGradients grads;
    if (gradient != nullptr) {
      std::fill_n(gradient, n_tri_ + n_mlp_, 0.0);
      grads = {gradient, gradient + n_tri_};
    }
    *cost = cost_.Loss(params, grads);
    if (tv_weight_ > 0) {
      *cost += field_->triplane().TotalVariation(parameters, tv_weight_,
                                                 gradient);
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return n_tri_ + n_mlp_; }

 private:
  const MotionField* field_;
  const SceneFlowCost cost_;
  double tv_weight_;
  int n_tri_, n_mlp_;
};

// Forwards Ceres' per-iteration summaries to the progress callback.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(const FlowPretrainOptions& options,
                   const PretrainStopwatch& clock)
      : options_(options), clock_(clock) {}
  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& summary) override {
    ReportPretrainProgress(options_, summary.iteration, options_.iterations,
                           clock_.seconds(), summary.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const FlowPretrainOptions& options_;
  const PretrainStopwatch& clock_;
};

// Makes a Ceres solver run the iterations asked for rather than stop on its
// default tolerances, which are tuned for cost scales of order 1, and report
// each one to `callback`.
template <typename SolverOptions>
void RunAllIterations(int iterations, ceres::IterationCallback* callback,
                      SolverOptions* options) {
  options->max_num_iterations = iterations;
  options->function_tolerance = 1e-15;
  options->gradient_tolerance = 1e-20;
  options->parameter_tolerance = 1e-15;
  options->callbacks.push_back(callback);
}

int FitWithLbfgs(const std::vector<SceneFlowSample>& samples,
                 const FlowPretrainOptions& options,
                 const PretrainStopwatch& clock, MotionField* field) {
  std::mt19937 rng(options.seed);
  SceneFlowBatch subset;
  subset.Assign(samples, RandomSubset(static_cast<int>(samples.size()),
                                      options.lbfgs_max_samples, &rng));
  std::vector<double> x = field->triplane_params();
  x.insert(x.end(), field->mlp_params().begin(), field->mlp_params().end());
  ceres::GradientProblem problem(
      new SceneFlowObjective(field, &subset, options.tv_weight));
  ceres::GradientProblemSolver::Options solver_options;
  solver_options.line_search_direction_type = ceres::LBFGS;
  solver_options.use_approximate_eigenvalue_bfgs_scaling = true;
  ProgressCallback callback(options, clock);
  RunAllIterations(options.iterations, &callback, &solver_options);
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(solver_options, problem, x.data(), &summary);
  VLOG(1) << summary.FullReport();
  const int n_tri = field->triplane().num_params();
  std::copy(x.begin(), x.begin() + n_tri, field->triplane_params().begin());
  std::copy(x.begin() + n_tri, x.end(), field->mlp_params().begin());
  return summary.iterations.empty()
             ? 0
             : summary.iterations.back().iteration;
}

int FitWithLm(const std::vector<SceneFlowSample>& samples,
              const FlowPretrainOptions& options,
              const PretrainStopwatch& clock, MotionField* field) {
  const int batch_size =
      std::min<int>(options.batch_size, static_cast<int>(samples.size()));
  const int64_t num_params =
      field->triplane().num_params() + field->mlp().num_params();
  const int64_t jacobian_values = 3 * int64_t{batch_size} * num_params;
  if (jacobian_values > options.lm_max_jacobian_values) {
    throw InputError(
        "the lm pretraining solver would need a dense " +
        std::to_string(3 * batch_size) + " x " + std::to_string(num_params) +
        " Jacobian (limit " + std::to_string(options.lm_max_jacobian_values) +
        " values); use the adam or lbfgs solver, a smaller batch or a "
        "smaller field");
  }
  std::mt19937 rng(options.seed);
  SceneFlowBatch batch;
  batch.Assign(samples, RandomSubset(static_cast<int>(samples.size()),
                                     batch_size, &rng));
  ceres::Problem problem;
  problem.AddResidualBlock(new SceneFlowResiduals(field, &batch), nullptr,
                           field->triplane_params().data(),
                           field->mlp_params().data());
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  ProgressCallback callback(options, clock);
  RunAllIterations(options.iterations, &callback, &solver_options);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  VLOG(1) << summary.FullReport();
  return summary.iterations.empty()
             ? 0
             : summary.iterations.back().iteration;
}

}  // namespace

double FitRmse(const MotionField& field,
               const std::vector<SceneFlowSample>& samples) {
  if (samples.empty()) return 0.0;
  constexpr int kChunk = 65536;
  SceneFlowBatch batch;
  const SceneFlowCost cost(&field, &batch);
  std::vector<int> indices;
  double sum = 0;
  for (size_t begin = 0; begin < samples.size(); begin += kChunk) {
    const size_t end = std::min(samples.size(), begin + kChunk);
    indices.resize(end - begin);
    std::iota(indices.begin(), indices.end(), static_cast<int>(begin));
    batch.Assign(samples, indices);
    sum += 2.0 * cost.Loss(field.params(), {}) * indices.size();
  }
  return std::sqrt(sum / samples.size());
}

FlowPretrainReport PretrainMotionField(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, MotionField* field) {
  CHECK(field != nullptr);
  if (options.solver != PretrainSolver::kAdam && options.comm != nullptr &&
      options.comm->size() > 1) {
    throw InputError("the " + PretrainSolverName(options.solver) +
                     " pretraining solver runs in one process; on several "
                     "ranks use --solver adam");
  }
  FlowPretrainReport report;
  // The fits below take the TV weight in the data term's units.
  const FlowPretrainOptions fit = StartPretraining(samples, options, &report);
  report.initial_rmse = FitRmse(*field, samples);
  const PretrainStopwatch clock;
  switch (options.solver) {
    case PretrainSolver::kAdam:
      report.iterations = FitWithAdam(samples, fit, clock,
                                      PretrainLossScale(report), field);
      break;
    case PretrainSolver::kLbfgs:
      report.iterations = FitWithLbfgs(samples, fit, clock, field);
      break;
    case PretrainSolver::kLm:
      report.iterations = FitWithLm(samples, fit, clock, field);
      break;
  }
  report.seconds = clock.seconds();
  report.fit_rmse = FitRmse(*field, samples);
  CheckPretrainedField(AllFinite(field->triplane_params()) &&
                           AllFinite(field->mlp_params()) &&
                           std::isfinite(report.fit_rmse),
                       report, options);
  return report;
}

}  // namespace es
