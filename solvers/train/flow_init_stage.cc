#include "solvers/train/flow_init_stage.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "core/base/input_error.h"
#include "core/base/stage_profile.h"
#include "core/fields/field_io.h"
#include "core/flow/scene_flow_io.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/model/dynamic_set.h"
#include "solvers/train/flow_init_metrics.h"

namespace es {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Seconds left when `done` of `total` equal steps took `seconds`.
double Eta(double seconds, int done, int total) {
  return done > 0 ? seconds / done * (total - done) : 0;
}

// Keeps a random subset of at most `max` samples.
void Subsample(int max, uint32_t seed, std::vector<SceneFlowSample>* samples) {
  if (static_cast<int>(samples->size()) <= max) return;
  std::mt19937 rng(seed);
  std::shuffle(samples->begin(), samples->end(), rng);
  samples->resize(max);
}

// The lifting as asked, with a progress line (and ETA) per frame pair.
SceneFlowOptions LiftingWithProgress(const FlowInitStageOptions& options) {
  SceneFlowOptions o = options.flow;
  if (!options.free_line_of_sight) o.lifting.line_of_sight_weight = 1.0;
  const Clock::time_point start = Clock::now();
  o.progress = [start](int k, int n, const std::string& a,
                       const std::string& b, long count) {
    std::printf("flow %d/%d %s -> %s: %ld samples  ETA %.0f s\n", k + 1, n,
                a.c_str(), b.c_str(), count,
                Eta(SecondsSince(start), k + 1, n));
    std::fflush(stdout);
  };
  return o;
}

}  // namespace

SceneFlowResult LiftWaterFlow(const Scene& scene, const GaussianSet& model,
                              const FlowInitStageOptions& options) {
  SceneFlowResult lifted;
  {
    const SceneFlowOptions lifting = LiftingWithProgress(options);
    ScopedStage timer(Stage::kOpticalFlow);
    lifted = LiftSceneFlow(scene, model, lifting);
  }
  const LiftingStats& s = lifted.stats;
  std::printf(
      "water pixels from %s; %ld candidates: %ld accepted, rejected %ld no "
      "depth, %ld depth edge, %ld outside, %ld inconsistent, %ld not water\n",
      lifted.used_masks ? "masks" : "the model's dynamic channel",
      s.candidates, s.accepted, s.no_depth, s.depth_edge, s.outside,
      s.inconsistent, s.not_water);
  if (lifted.samples.empty()) {
    throw InputError(
        scene.dir +
        ": no scene-flow sample survived the checks (see the counts above); "
        "loosen --max_fb_px / --max_depth_jump or check the water masks. "
        "Nothing was written.");
  }
  Subsample(options.max_samples, options.sample_seed, &lifted.samples);
  if (options.oracle) {
    ReplaceWithTruth(LoadMotionGt(options.scene_dir), *options.oracle,
                     &lifted.samples);
    std::printf("--oracle_velocity %s: every sample now has the true "
                "velocity at its position\n",
                OracleVelocityName(options.oracle).c_str());
  }
  return lifted;
}

FlowPretrainReport PretrainFieldOnSamples(
    const FlowPretrainer& pretrain, const SceneFlowResult& lifted,
    const GaussianSet& model, const std::vector<int>& dynamic,
    const FlowPretrainOptions& options, TrainingHistory* history,
    MotionField* field) {
  Eigen::Vector3d lo, hi;
  FieldBox(model, dynamic, &lo, &hi);
  field->SetBox(lo, hi);
  FlowPretrainOptions fit_options = options;
  const int iterations = fit_options.iterations;
  fit_options.progress = [history, iterations](int it, double seconds,
                                               double rmse) {
    std::printf("pretrain iteration %d/%d  %.1f s  batch rmse %.3g  ETA "
                "%.0f s\n",
                it, iterations, seconds, rmse, Eta(seconds, it, iterations));
    std::fflush(stdout);
    history->Add(it, seconds, {rmse});
  };
  const FlowPretrainReport fit = pretrain(lifted.samples, fit_options, field);
  std::printf("fit rmse %.4g (targets rms %.4g, start %.4g) in %.1f s\n",
              fit.fit_rmse, fit.target_rms, fit.initial_rmse, fit.seconds);
  return fit;
}

FlowInitStageResult RunFlowInitStage(const FlowInitStageOptions& o,
                                     const FlowPretrainer& pretrain) {
  if (o.oracle && !HasMotionGt(o.scene_dir)) {
    throw InputError(o.scene_dir + "/gt/velocity_grid.bin: missing; "
                     "--oracle_velocity needs a synthetic scene with "
                     "ground-truth motion (es_synth). Nothing was "
                     "written.");
  }
  const Clock::time_point start = Clock::now();
  const std::string static_path =
      o.static_path.empty() ? o.scene_dir + "/static.ply" : o.static_path;
  const std::string out_dir = o.out_dir.empty() ? o.scene_dir : o.out_dir;

  // With several ranks (o.pretrain.comm), each lifts every frame pair and
  // fits its shards of each batch; rank 0 alone writes.
  const bool lead = o.pretrain.comm == nullptr || o.pretrain.comm->rank() == 0;
  if (lead)
    PrepareOutputDirectory(out_dir, o.out_dir.empty() ? "scene" : "out");
  const Scene scene = LoadScene(o.scene_dir, o.scene);
  const GaussianSet model = ReadPly(static_path);
  const std::vector<int> dynamic = DynamicSet(model, o.dynamic_threshold);
  if (dynamic.empty()) {
    throw InputError(
        static_path + ": no dynamic Gaussians (sigmoid(dynamic_logit) > " +
        std::to_string(o.dynamic_threshold) +
        "), so there is no water for a motion field; train Stage 1 with "
        "water masks or lower --dynamic_threshold. Nothing was written.");
  }
  std::printf("%d frames, %d of %d Gaussians dynamic\n",
              static_cast<int>(scene.frames.size()),
              static_cast<int>(dynamic.size()), model.size());
  StageProfile::Get().Start(o.profile);
  FlowInitStageResult r;
  r.num_dynamic = static_cast<int>(dynamic.size());
  r.lifted = LiftWaterFlow(scene, model, o);

  MotionField field(o.field);
  TrainingHistory history(out_dir + "/flow_history.csv", {"rmse"});
  r.fit = PretrainFieldOnSamples(pretrain, r.lifted, model, dynamic,
                                 o.pretrain, &history, &field);
  StageProfile::Get().PrintAndStop(
      "es_flowinit, " + std::to_string(o.pretrain.iterations) +
      " pretraining iterations of " + std::to_string(o.pretrain.batch_size) +
      " samples (optical flow + lifting: once, before them)");

  if (lead) {
    SaveMotionField(field, out_dir + "/motion_field.bin");
    SaveSceneFlowSamples(r.lifted.samples,
                         out_dir + "/scene_flow_samples.bin");
    history.Write();
  }
  r.seconds = SecondsSince(start);
  if (HasMotionGt(o.scene_dir)) {
    std::vector<Eigen::Vector3d> points;
    for (int i : dynamic) {
      points.emplace_back(model.means[3 * i], model.means[3 * i + 1],
                          model.means[3 * i + 2]);
    }
    const VelocityFunction truth = LoadMotionGt(o.scene_dir);
    r.field_gt = EvaluateMotionGt(field, points, truth);
    r.samples_gt = EvaluateSamplesGt(r.lifted.samples, truth);
    std::printf("ground truth: epe %.4g (mean speed %.4g, relative %.3f, "
                "speed ratio %.2f); lifted samples: relative %.3f, speed "
                "ratio %.2f\n",
                r.field_gt->epe, r.field_gt->mean_speed, r.field_gt->rel_epe,
                r.field_gt->speed_ratio, r.samples_gt->rel_epe,
                r.samples_gt->speed_ratio);
  }
  if (lead) WriteFlowMetrics(out_dir + "/flow_metrics.json", o, r);
  std::printf("wrote %s/motion_field.bin, scene_flow_samples.bin, "
              "flow_metrics.json and flow_history.csv (%.1f s)\n",
              out_dir.c_str(), r.seconds);
  return r;
}

}  // namespace es
