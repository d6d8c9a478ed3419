#include "solvers/train/joint_stage.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/base/input_error.h"
#include "core/base/iteration_parts.h"
#include "core/base/stage_profile.h"
#include "core/fields/field_io.h"
#include "core/flow/scene_flow_io.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/loop/loop_model.h"
#include "costs/water_input_noise.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "solvers/train/data_parallel.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/static_eval.h"
#include "solvers/train/joint_training_steps.h"
#include "costs/scene_flow_prior.h"
#include "solvers/train/training_history.h"

namespace es {
namespace {

namespace fs = std::filesystem;

std::string InDir(const std::string& dir, const char* name) {
  return (fs::path(dir) / name).string();
}

// Throws InputError for a scene Stage 3 cannot train on.
void CheckScene(const JointStageOptions& o, const Scene& scene) {
  if (scene.train.empty())
    throw InputError(o.scene_dir + ": no training frames");
  // A loop longer than the video has frames no training image shows (and
  // its cost grows with L).
  const int frames = static_cast<int>(scene.frames.size());
  if (o.trainer.cycle_length > frames) {
    throw InputError("--cycle_length=" +
                     std::to_string(o.trainer.cycle_length) +
                     ": must be <= " + std::to_string(frames) + " (" +
                     o.scene_dir + " has " + std::to_string(frames) +
                     " frames)");
  }
}

void WriteMetrics(const std::string& path, const JointStageResult& r,
                  const LoopModel& model, bool random_start) {
  const LoopMetrics& m = r.test;
  WriteJsonFile(path, {{"psnr_test", m.psnr},
                       {"ssim_test", m.ssim},
                       {"psnr_test_water", m.psnr_water},
                       {"ssim_test_water", m.ssim_water},
                       {"psnr_test_static", m.psnr_static},
                       {"psnr_test_far_scenery", m.psnr_far_scenery},
                       {"test_frames", m.frames},
                       {"seconds", r.seconds},
                       {"iterations", r.iterations},
                       {"num_gaussians", model.gaussians.size()},
                       {"num_dynamic", model.num_dynamic()},
                       {"cycle_length", model.cycle_length},
                       {"motion_field", model.motion.has_value()},
                       {"flow_init", r.flow_init},
                       {"residual_field", model.residual.has_value()},
                       {"random_start", random_start},
                       {"final_loss", r.final_loss},
                       {"stage1_psnr_test", r.stage1.psnr},
                       {"stage1_psnr_test_water", r.stage1.psnr_water},
                       {"stage1_psnr_test_static", r.stage1.psnr_static},
                       {"stage1_psnr_test_far_scenery",
                        r.stage1.psnr_far_scenery}});
}

// The water losses' input noise (costs/water_input_noise.h): `sigma` on
// every channel, or, for sigma < 0, estimated from the training frames.
void SetInputNoise(double sigma, const Scene& scene,
                   JointTrainerOptions* trainer) {
  std::array<double, 3> noise = {sigma, sigma, sigma};
  if (sigma < 0) noise = EstimateInputNoise(scene.frames, scene.train);
  trainer->water_energy.input_noise = noise;
  trainer->water_texture.input_noise = noise;
  if (sigma == 0) return;  // off: nothing to say
  if (!HasInputNoise(noise)) {
    std::printf("input noise: none found in the training frames\n");
    return;
  }
  std::printf("input noise, std per opponent channel: %.4f %.4f %.4f (%s)\n",
              noise[0], noise[1], noise[2],
              sigma < 0 ? "estimated from the training frames" : "given");
}

// V pretrained by Stage 2 (<init>/motion_field.bin) when there is one and
// it is wanted; nullopt starts V from scratch.
std::optional<MotionField> PretrainedMotion(const JointStageOptions& o,
                                            bool* flow_init) {
  *flow_init = false;
  if (!o.trainer.use_motion) return std::nullopt;
  const std::string path = InDir(o.init_dir, "motion_field.bin");
  if (!o.flow_init) {
    std::printf("V: from scratch (--no_flow_init)\n");
    return std::nullopt;
  }
  if (!fs::exists(path)) {
    std::printf("V: from scratch (%s not found)\n", path.c_str());
    return std::nullopt;
  }
  *flow_init = true;
  std::printf("V: pretrained from %s\n", path.c_str());
  return LoadMotionField(path);
}

// Gives the trainer Stage 2's samples as a prior on V when one is wanted
// and V was pretrained from them.
void AddFlowPrior(const JointStageOptions& o, bool flow_init,
                  JointStageTrainer* trainer) {
  const JointTrainerOptions& t = o.trainer;
  if (t.flow_prior.weight <= 0 || !t.use_motion) return;
  const std::string path = InDir(o.init_dir, "scene_flow_samples.bin");
  if (!flow_init || !fs::exists(path)) {
    std::printf("scene-flow prior: off (%s)\n",
                flow_init ? (path + " not found").c_str()
                          : "V is not pretrained");
    return;
  }
  std::vector<SceneFlowSample> samples = LoadSceneFlowSamples(path);
  if (samples.empty()) {
    std::printf("scene-flow prior: off (%s holds no samples)\n",
                path.c_str());
    return;
  }
  if (o.flow_prior_to_field) {
    TargetFieldAtSamples(
        LoadMotionField(InDir(o.init_dir, "motion_field.bin")), &samples);
  }
  std::printf("scene-flow prior: %zu %s from %s, weight %g -> %g\n",
              samples.size(),
              o.flow_prior_to_field ? "points of Stage 2's V" : "samples",
              path.c_str(), t.flow_prior.weight,
              t.flow_prior.weight * t.flow_prior.final_factor);
  trainer->SetSceneFlowPrior(std::move(samples));
}

// Splits the static model's large water Gaussians into particles
// (particles.particle_pixels > 0).
void SplitWater(const JointStageOptions& o, const Scene& scene,
                GaussianSet* gaussians) {
  if (o.particles.particle_pixels <= 0) return;
  WaterParticleOptions particles = o.particles;
  particles.dynamic_threshold = o.trainer.dynamic_threshold;
  particles.seed = o.trainer.seed;
  const ParticleSplitStats split = SplitWaterIntoParticles(
      particles, scene.frames, scene.train, gaussians);
  std::printf("water split into particles: %d blobs -> %d particles "
              "(water Gaussians %d -> %d)\n",
              split.blobs, split.particles, split.dynamic_before,
              split.dynamic_after);
}

// Whether this process evaluates and writes: rank 0, or the only one.
bool LeadRank(const JointTrainerOptions& o) {
  return o.comm == nullptr || o.comm->rank() == 0;
}

// The history.csv columns after the iteration and time.
const std::vector<std::string> kHistoryColumns = {
    "loss",      "photometric", "mask",      "residual",
    "gaussians", "dynamic",     "psnr_test", "psnr_test_water"};

// The history's first row: the looping model before any step, beside
// Stage 1's figures, so that a drop at the start of Stage 3 shows.
void RecordStart(const LoopMetrics& stage1, const LoopMetrics& start,
                 TrainingHistory* history) {
  std::printf("iter 0: held-out PSNR %.2f dB, water %.2f dB, scenery %.2f "
              "dB (Stage 1's model: %.2f, %.2f, %.2f dB)\n",
              start.psnr, start.psnr_water, start.psnr_static, stage1.psnr,
              stage1.psnr_water, stage1.psnr_static);
  history->Add(0, 0.0,
               {NAN, NAN, NAN, NAN, NAN, NAN, start.psnr, start.psnr_water});
  history->Write();
}

// What Train leaves for the end of the run.
struct TrainingOutcome {
  double seconds = 0;       // this session's training time, evaluations not
  double final_loss = NAN;  // mean loss of the last logged interval
  // The last history row, still without the final metrics (empty when the
  // run had nothing left to log).
  std::vector<double> final_row;
};

// Runs the trainer to o.trainer.iterations with progress lines (ETA,
// held-out PSNR every eval_interval), history rows and periodic
// checkpoints.
TrainingOutcome Train(const JointStageOptions& o, const Scene& scene,
                      const std::string& checkpoint_path,
                      double seconds_before, TrainingHistory* history,
                      JointStageTrainer* trainer) {
  const JointTrainerOptions& options = o.trainer;
  const bool lead = LeadRank(options);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  double eval_seconds = 0;  // kept out of the training clock
  const auto training_seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - start).count() -
           eval_seconds;
  };
  const int64_t first = trainer->iteration();
  int64_t last_row = first;
  // loss, photometric, mask, residual, motion and detail energy, texture,
  // the loop's texture
  double sums[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int64_t counted = 0;             // steps in the sums
  int64_t loop_counted = 0;        // of them, those that scored the loop
  TrainingOutcome outcome;
  StageProfile::Get().Start(o.profile);
  while (trainer->iteration() < options.iterations) {
    const bool loop_due = LoopTextureDue(options, trainer->iteration());
    const JointIterationStats s = trainer->Step();
    if (!s.skipped) {  // a skipped step's loss is not finite
      sums[0] += s.loss;
      sums[1] += s.photometric;
      sums[2] += s.mask;
      sums[3] += s.residual;
      sums[4] += s.energy.motion;
      sums[5] += s.energy.detail;
      sums[6] += s.texture;
      sums[7] += s.loop_texture;
      ++counted;
      if (loop_due) ++loop_counted;
    }
    const int64_t it = trainer->iteration();
    if (s.densified.split + s.densified.cloned > 0) {
      std::printf("iter %lld: water densified, %d split, %d cloned (water "
                  "Gaussians %d)\n",
                  static_cast<long long>(it), s.densified.split,
                  s.densified.cloned, trainer->model().num_dynamic());
    }
    const bool log = o.log_interval > 0 &&
                     (it % o.log_interval == 0 || it == options.iterations);
    const bool eval = o.eval_interval > 0 && it % o.eval_interval == 0 &&
                      it < options.iterations;  // the end is in the caller
    if (log || eval) {
      const double window = counted > 0 ? counted : NAN;
      outcome.final_loss = sums[0] / window;
      const double elapsed = training_seconds();
      LoopMetrics held_out;
      if (eval && lead) {
        const Clock::time_point eval_start = Clock::now();
        ScopedPass pass(Pass::kEvaluation);
        ScopedStage timer(Stage::kEvaluation);
        held_out = EvaluateLoopModel(trainer->model(), scene.frames,
                                     scene.test, trainer->render_options());
        eval_seconds +=
            std::chrono::duration<double>(Clock::now() - eval_start).count();
      }
      const std::vector<double> row = {
          sums[0] / window,
          sums[1] / window,
          sums[2] / window,
          sums[3] / window,
          static_cast<double>(trainer->model().gaussians.size()),
          static_cast<double>(s.num_dynamic),
          eval ? held_out.psnr : NAN,
          eval ? held_out.psnr_water : NAN};
      if (it < options.iterations) {
        ScopedStage timer(Stage::kCheckpoint);
        history->Add(it, seconds_before + elapsed, row);
        if (lead) history->Write();
      } else {
        outcome.final_row = row;  // completed with the final metrics
      }
      const double rate = (it - first) / std::max(elapsed, 1e-9);
      std::printf(
          "iter %lld/%d  loss %.5f (photo %.5f mask %.5f res %.2e)  "
          "dynamic %d  %.2f it/s  ETA %.0f s",
          static_cast<long long>(it), options.iterations, outcome.final_loss,
          sums[1] / window, sums[2] / window, sums[3] / window,
          s.num_dynamic, rate, (options.iterations - it) / rate);
      if (options.water_energy.motion_weight > 0 ||
          options.water_energy.detail_weight > 0) {
        std::printf("  energy motion %.4f detail %.4f", sums[4] / window,
                    sums[5] / window);
      }
      if (options.water_texture.weight > 0)
        std::printf("  texture %.5f", sums[6] / window);
      if (options.loop_texture_weight > 0)
        std::printf("  loop texture %.5f",
                    sums[7] / (loop_counted > 0 ? loop_counted : NAN));
      if (eval) std::printf("  held-out PSNR %.2f dB", held_out.psnr);
      std::printf("\n");
      std::fflush(stdout);
      last_row = it;
      for (double& v : sums) v = 0;
      counted = 0;
      loop_counted = 0;
    }
    // Not right after a skipped (non-finite) step: keep the last good one.
    if (lead && o.checkpoint_interval > 0 &&
        it % o.checkpoint_interval == 0 && trainer->last_step_ok()) {
      ScopedStage timer(Stage::kCheckpoint);
      WriteJointCheckpoint(trainer->Save(), checkpoint_path);
    }
  }
  outcome.seconds = training_seconds();
  if (trainer->skipped_steps() > 0)
    std::printf("%lld step(s) skipped for a non-finite loss or gradient\n",
                static_cast<long long>(trainer->skipped_steps()));
  if (options.batch_frames > 1) {
    std::printf("batches of %d frames on %d rank(s); allreduce %.2f MB per "
                "iteration\n",
                options.batch_frames,
                options.comm != nullptr ? options.comm->size() : 1,
                trainer->allreduce_bytes() / 1e6);
  }
  PrintProfileAndStop(
      "es_train, " + std::to_string(trainer->iteration() - first) +
      " iterations, " + std::to_string(trainer->model().gaussians.size()) +
      " Gaussians, " + std::to_string(trainer->model().num_dynamic()) +
      " dynamic");
  if (outcome.final_row.empty() && trainer->iteration() > last_row) {
    const double window = counted > 0 ? counted : NAN;
    outcome.final_row = {
        sums[0] / window,
        sums[1] / window,
        sums[2] / window,
        sums[3] / window,
        static_cast<double>(trainer->model().gaussians.size()),
        static_cast<double>(trainer->model().num_dynamic()),
        NAN,
        NAN};
  }
  return outcome;
}

// The last history row carries the final model's held-out metrics.
void RecordFinalMetrics(const LoopMetrics& metrics, int64_t iteration,
                        double seconds, std::vector<double> final_row,
                        TrainingHistory* history) {
  if (!final_row.empty()) {
    final_row[6] = metrics.psnr;
    final_row[7] = metrics.psnr_water;
    history->Add(iteration, seconds, final_row);
  } else {
    history->SetFinalMetrics(iteration, seconds,
                             {{"psnr_test", metrics.psnr},
                              {"psnr_test_water", metrics.psnr_water}});
  }
  history->Write();
}

}  // namespace

JointStageResult RunJointStage(const JointStageOptions& options,
                               const JointTrainerFactory& make_trainer) {
  // With several ranks, rank 0 alone evaluates and writes (the others
  // train the same model; their stdout is silenced by the app).
  const bool lead = LeadRank(options.trainer);
  if (lead) PrepareOutputDirectory(options.out_dir, "out");
  const Scene scene = LoadScene(options.scene_dir, options.scene);
  CheckScene(options, scene);
  JointStageOptions o = options;
  SetInputNoise(options.input_noise, scene, &o.trainer);
  const std::string static_ply = InDir(o.init_dir, "static.ply");
  GaussianSet initial = ReadPly(static_ply);
  if (initial.size() == 0)
    throw InputError(static_ply + ": holds no Gaussians");
  std::printf("loaded %s: %d Gaussians, SH degree %d\n", static_ply.c_str(),
              initial.size(), initial.sh_degree);
  JointStageResult r;
  if (lead && o.eval_interval > 0 && !scene.test.empty()) {
    // The same renders and figures as EvaluateLoopModel's for a model
    // without motion.
    const StaticMetrics stage1 = EvaluateStatic(
        initial, scene.frames, scene.test, JointRenderOptions(o.trainer));
    r.stage1 = {stage1.frames,      stage1.psnr,       stage1.ssim,
                stage1.psnr_water,  stage1.ssim_water, stage1.psnr_static,
                stage1.psnr_far_scenery};
  }
  std::optional<MotionField> motion = PretrainedMotion(o, &r.flow_init);
  SplitWater(o, scene, &initial);

  const std::unique_ptr<JointStageTrainer> trainer_owner =
      make_trainer(&scene.frames, scene.train, o.trainer, std::move(initial),
                   std::move(motion));
  JointStageTrainer& trainer = *trainer_owner;
  if (!o.device_name.empty())
    std::printf("training on %s\n", o.device_name.c_str());
  AddFlowPrior(o, r.flow_init, &trainer);
  std::printf("dynamic Gaussians: %d of %d; V %s, D %s; masks %s\n",
              trainer.model().num_dynamic(), trainer.model().gaussians.size(),
              o.trainer.use_motion ? "on" : "off",
              o.trainer.use_residual ? "on" : "off",
              trainer.uses_masks() ? "on" : "off");
  const std::string checkpoint_path = InDir(o.out_dir, "joint_checkpoint.bin");
  if (o.resume && fs::exists(checkpoint_path)) {
    const JointCheckpoint checkpoint = ReadJointCheckpoint(checkpoint_path);
    CheckResumedBatch(checkpoint.batch_frames, o.trainer.batch_frames,
                      checkpoint_path);
    trainer.Restore(checkpoint, checkpoint_path);
    std::printf("resumed from %s at iteration %lld\n",
                checkpoint_path.c_str(),
                static_cast<long long>(trainer.iteration()));
  }
  TrainingHistory history(InDir(o.out_dir, "history.csv"), kHistoryColumns);
  const double seconds_before = history.Resume(trainer.iteration());
  if (lead && trainer.iteration() == 0 && o.eval_interval > 0 &&
      !scene.test.empty()) {
    RecordStart(r.stage1,
                EvaluateLoopModel(trainer.model(), scene.frames, scene.test,
                                  trainer.render_options()),
                &history);
  }
  const TrainingOutcome outcome =
      Train(o, scene, checkpoint_path, seconds_before, &history, &trainer);
  r.seconds = outcome.seconds;
  r.final_loss = outcome.final_loss;
  r.iterations = trainer.iteration();
  if (!lead) return r;

  int pruned = 0;
  const LoopModel model = trainer.FinalModel(&pruned);
  std::printf("pruned %d invisible Gaussians (opacity < 1/255 in every "
              "frame)\n", pruned);
  r.num_gaussians = model.gaussians.size();
  r.num_dynamic = model.num_dynamic();
  SaveLoopModel(model, o.out_dir);
  r.test = EvaluateLoopModel(model, scene.frames, scene.test,
                             trainer.render_options());
  RecordFinalMetrics(r.test, r.iterations, seconds_before + r.seconds,
                     outcome.final_row, &history);
  // Last: with loop.txt it tells the driver (eulersplat) that the
  // stage is done, so nothing may fail after it.
  WriteMetrics(InDir(o.out_dir, "metrics.json"), r, model,
               o.trainer.random_start);
  return r;
}

}  // namespace es
