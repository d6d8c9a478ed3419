#include "solvers/train/cuda/device_flow_pretrain.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glog/logging.h>

#include "core/fields/cuda/device_field_workspace.h"
#include "core/fields/cuda/device_motion_field.h"
#include "core/base/input_error.h"
#include "core/base/stage_profile.h"
#include "solvers/optim/cuda/device_adam.h"
#include "costs/cuda/device_scene_flow_loss.h"
#include "solvers/train/cuda/training_kernels.h"
#include "solvers/train/divergence_guard.h"
#include "solvers/train/flow_pretrain_steps.h"

namespace es {
namespace cuda {
namespace {

// FitRmse on the device, over the samples in the CPU's chunks.
double DeviceFitRmse(const FieldParams& params, DeviceSceneFlowLoss* loss) {
  constexpr int kChunk = 65536;
  const int n = loss->num_samples();
  std::vector<int> indices;
  double sum = 0;
  for (int begin = 0; begin < n; begin += kChunk) {
    indices.resize(std::min(n, begin + kChunk) - begin);
    std::iota(indices.begin(), indices.end(), begin);
    sum += 2.0 * loss->AddLossAndGradient(params, indices, 1.0, {}) *
           indices.size();
  }
  return std::sqrt(sum / n);
}

// True when both blocks hold only finite values (one int comes back).
bool AllFinite(const DeviceFieldBlocks& blocks, DeviceBuffer<int>* flag) {
  flag->Resize(1);
  flag->Zero();
  for (const DeviceBuffer<double>* b : {&blocks.triplane, &blocks.mlp}) {
    FlagNonFinite(static_cast<long long>(b->size()), b->data(),
                  flag->data());
  }
  int value = 0;
  flag->Download(&value);
  return value == 0;
}

// MaxMagnitude of both blocks: two integers come back.
std::vector<double> MaxMagnitudes(const DeviceFieldBlocks& blocks,
                                  DeviceBuffer<unsigned long long>* bits) {
  bits->Resize(2);
  bits->Zero();
  RaiseMaxMagnitudeBits(static_cast<long long>(blocks.triplane.size()),
                        blocks.triplane.data(), bits->data());
  RaiseMaxMagnitudeBits(static_cast<long long>(blocks.mlp.size()),
                        blocks.mlp.data(), bits->data() + 1);
  std::vector<double> magnitudes;
  for (unsigned long long b : bits->Download())
    magnitudes.push_back(MagnitudeOfBits(b));
  return magnitudes;
}

// FitWithAdam (flow_pretrain.cc) with x, the gradients and moments on the
// device; `blocks` and `loss_scale` as PretrainGuardedBlocks and
// PretrainLossScale give them.
int FitWithAdam(const DeviceMotionField& field,
                const FlowPretrainOptions& options,
                const PretrainStopwatch& clock,
                const std::vector<GuardedBlock>& blocks, double loss_scale,
                DeviceSceneFlowLoss* loss, DeviceFieldBlocks* x) {
  const int n_tri = field.triplane().num_params();
  const int n_mlp = field.mlp().num_params();
  DeviceFieldBlocks g, m, v;
  g.Zeros(n_tri, n_mlp);
  m.Zeros(n_tri, n_mlp);
  v.Zeros(n_tri, n_mlp);
  DeviceBuffer<double> tv_scratch;
  DeviceBuffer<int> flag;
  DeviceBuffer<unsigned long long> magnitude_bits;
  PretrainBatches batches(options.seed, loss->num_samples(),
                          options.batch_size);
  const AdamOptions adam = PretrainAdamOptions(options);
  DivergenceGuard guard("V pretraining", options.max_nonfinite_steps,
                        "no field was written");
  for (int it = 1; it <= options.iterations; ++it) {
    ScopedStage timer(Stage::kIteration);
    g.triplane.Zero();
    g.mlp.Zero();
    const double value = loss->AddLossAndGradient(
        x->params(), batches.Next(), 1.0, g.gradients());
    if (options.tv_weight > 0) {
      field.triplane().TotalVariation(x->triplane.data(), options.tv_weight,
                                      g.triplane.data(), &tv_scratch);
    }
    if (!guard.Accept(it, std::isfinite(value) && AllFinite(g, &flag)))
      continue;
    guard.CheckLoss(it, value, loss_scale, blocks);
    const double decay = PretrainLrDecay(options, it);
    DeviceAdamUpdate(adam, it, options.lr_triplane * decay, n_tri,
                     g.triplane.data(), m.triplane.data(), v.triplane.data(),
                     x->triplane.data());
    DeviceAdamUpdate(adam, it, options.lr_mlp * decay, n_mlp, g.mlp.data(),
                     m.mlp.data(), v.mlp.data(), x->mlp.data());
    guard.CheckBlocks(it, blocks, MaxMagnitudes(*x, &magnitude_bits));
    ReportPretrainProgress(options, it, options.iterations, clock.seconds(),
                           value);
  }
  return options.iterations;
}

}  // namespace

FlowPretrainReport PretrainMotionFieldOnDevice(
    const std::vector<SceneFlowSample>& samples,
    const FlowPretrainOptions& options, MotionField* field) {
  CHECK(field != nullptr);
  if (options.solver != PretrainSolver::kAdam) {
    throw InputError("the " + PretrainSolverName(options.solver) +
                     " pretraining solver runs on the CPU only; use the "
                     "adam solver on the CUDA device, or --device cpu");
  }
  FlowPretrainReport report;
  const FlowPretrainOptions fit = StartPretraining(samples, options, &report);
  const DeviceMotionField device_field(*field);
  DeviceSceneFlowLoss loss(&device_field, samples);
  const int n_tri = field->triplane().num_params();
  const int n_mlp = field->mlp().num_params();
  DeviceFieldBlocks x;
  x.Upload(field->params(), n_tri, n_mlp);
  report.initial_rmse = DeviceFitRmse(x.params(), &loss);
  const PretrainStopwatch clock;
  report.iterations =
      FitWithAdam(device_field, fit, clock, PretrainGuardedBlocks(fit, *field),
                  PretrainLossScale(report), &loss, &x);
  report.seconds = clock.seconds();
  report.fit_rmse = DeviceFitRmse(x.params(), &loss);
  DeviceBuffer<int> flag;
  const bool finite = AllFinite(x, &flag) && std::isfinite(report.fit_rmse);
  x.triplane.Download(field->triplane_params().data());
  x.mlp.Download(field->mlp_params().data());
  CheckPretrainedField(finite, report, options);
  return report;
}

}  // namespace cuda
}  // namespace es
