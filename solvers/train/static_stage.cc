#include "solvers/train/static_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/model/gaussian_init.h"
#include "core/base/iteration_parts.h"
#include "core/base/stage_profile.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/train/data_parallel.h"
#include "solvers/train/densify_eta.h"
#include "solvers/train/training_history.h"

namespace es {
namespace {

// Written for every Gaussian of a scene without masks: clearly static.
constexpr double kStaticProbability = 0.01;

void Validate(const StaticStageOptions& o) {
  auto fail = [](const std::string& m) { throw InputError(m); };
  if (o.scene_dir.empty()) fail("--scene is required");
  if (o.out_dir.empty()) fail("--out is required");
  const StaticTrainerOptions& t = o.trainer;
  if (t.iterations <= 0)
    fail("--iterations must be positive, got " + std::to_string(t.iterations));
  if (t.max_sh_degree < 0 || t.max_sh_degree > kMaxShDegree)
    fail("--sh_degree must be in [0, 3], got " +
         std::to_string(t.max_sh_degree));
  if (t.ssim_weight < 0 || t.ssim_weight > 1)
    fail("--ssim_weight must be in [0, 1]");
  if (t.mask_weight < 0) fail("--mask_weight must be >= 0");
  if (o.checkpoint_every < 0) fail("--checkpoint_every must be >= 0");
  if (o.log_every < 0) fail("--log_every must be >= 0");
  if (o.eval_every < 0) fail("--eval_every must be >= 0");
  if (t.sh_degree_interval <= 0) fail("--sh_degree_interval must be positive");
  if (t.splat_lr.means_final > t.splat_lr.means_initial)
    fail("--lr_position_final must not exceed --lr_position");
  if (!(o.dynamic_threshold > 0 && o.dynamic_threshold < 1))
    fail("--dynamic_threshold must be in (0, 1)");
  const DensifyOptions& d = t.densify_options;
  if (d.interval <= 0) fail("--densify_interval must be positive");
  if (d.max_gaussians <= 0) fail("--max_gaussians must be positive");
  if (d.grad_threshold <= 0) fail("--densify_grad_threshold must be > 0");
  if (d.from_iteration < 0) fail("--densify_from must be >= 0");
  if (d.opacity_reset_interval < 0)
    fail("--opacity_reset_interval must be >= 0");
  if (!(d.percent_dense > 0)) fail("--percent_dense must be > 0");
  if (!(d.min_opacity >= 0 && d.min_opacity < 1))
    fail("--min_opacity must be in [0, 1)");
  if (!(d.max_screen_radius > 0))
    fail("--max_screen_radius must be > 0");
  if (!(d.max_world_scale >= 0 && std::isfinite(d.max_world_scale)))
    fail("--max_world_scale must be >= 0 and finite (0: off)");
}

void WriteMetrics(const StaticStageResult& r, const std::string& path) {
  WriteJsonFile(path, {{"psnr_test", r.test.psnr},
                       {"ssim_test", r.test.ssim},
                       {"psnr_test_water", r.test.psnr_water},
                       {"ssim_test_water", r.test.ssim_water},
                       {"psnr_test_static", r.test.psnr_static},
                       {"psnr_test_far_scenery", r.test.psnr_far_scenery},
                       {"ssim_test_static", r.test.ssim_static},
                       {"num_gaussians", r.num_gaussians},
                       {"num_dynamic", r.num_dynamic},
                       {"seconds", r.seconds},
                       {"iterations_per_second", r.iterations_per_second},
                       {"mask_precision", r.test.mask_precision},
                       {"mask_recall", r.test.mask_recall}});
}

int CountDynamic(const GaussianSet& model, double threshold) {
  int n = 0;
  for (double logit : model.dynamic_logits) n += Sigmoid(logit) > threshold;
  return n;
}

}  // namespace

Scene LoadStaticScene(const std::string& scene_dir,
                      const SceneOptions& options) {
  Scene scene = LoadScene(scene_dir, options);
  if (scene.train.empty()) throw InputError(scene_dir + ": no training frames");
  if (scene.points.empty())
    throw InputError(scene_dir + ": points3D is empty; nothing to seed");
  return scene;
}

GaussianSet InitialStaticGaussians(const Scene& scene) {
  return InitGaussiansFromPoints(scene.points, scene.point_colors, 0);
}

std::unique_ptr<StaticTrainer> MakeStaticTrainer(
    const Scene& scene, const StaticTrainerOptions& options) {
  return std::make_unique<StaticTrainer>(&scene.frames, scene.train, options,
                                         InitialStaticGaussians(scene));
}

GaussianSet StaticModel(const StaticStageTrainer& trainer) {
  GaussianSet model = trainer.gaussians();
  if (!trainer.uses_masks())
    std::fill(model.dynamic_logits.begin(), model.dynamic_logits.end(),
              Logit(kStaticProbability));
  return model;
}

StaticMetrics EvaluateHeldOut(const StaticStageTrainer& trainer,
                              const Scene& scene) {
  return EvaluateStatic(StaticModel(trainer), scene.frames, scene.test,
                        trainer.render_options());
}

StaticStageResult RunStaticStage(const StaticStageOptions& o,
                                 const StaticTrainerFactory& make_trainer) {
  Validate(o);
  // With several ranks, rank 0 alone evaluates and writes (the others
  // train the same model; their stdout is silenced by the app).
  const bool lead = o.trainer.comm == nullptr || o.trainer.comm->rank() == 0;
  if (lead) PrepareOutputDirectory(o.out_dir, "out");
  const std::string checkpoint_path = o.out_dir + "/checkpoint.bin";
  Checkpoint checkpoint;
  if (o.resume) checkpoint = ReadCheckpoint(checkpoint_path);
  const Scene scene = LoadStaticScene(o.scene_dir, o.scene);

  const std::unique_ptr<StaticStageTrainer> trainer_owner =
      make_trainer(scene, o.trainer);
  StaticStageTrainer& trainer = *trainer_owner;
  if (o.resume) {
    CheckResumedBatch(checkpoint.batch_frames, o.trainer.batch_frames,
                      checkpoint_path);
    if (checkpoint.gaussians.sh_degree > o.trainer.max_sh_degree)
      throw InputError(checkpoint_path + ": SH degree " +
                       std::to_string(checkpoint.gaussians.sh_degree) +
                       " exceeds --sh_degree");
    try {
      trainer.Restore(checkpoint);
    } catch (const InputError& e) {
      throw InputError(checkpoint_path + ": " + e.what());
    }
    std::printf("resumed from %s at iteration %lld\n", checkpoint_path.c_str(),
                static_cast<long long>(trainer.iteration()));
  }
  std::printf(
      "%zu frames (%zu train, %zu test), %zu points, extent %.3g, "
      "%s\n",
      scene.frames.size(), scene.train.size(), scene.test.size(),
      scene.points.size(), trainer.scene_extent(),
      trainer.uses_masks()
          ? "masks: learning the dynamic probability"
          : "no masks: no mask term, no Gaussian marked dynamic");

  TrainingHistory history(o.out_dir + "/history.csv",
                          {"loss", "photometric", "mask", "gaussians",
                           "dynamic", "psnr_test", "psnr_test_water"});
  const double seconds_before = history.Resume(trainer.iteration());

  using Clock = std::chrono::steady_clock;
  double eval_seconds = 0;  // kept out of the training clock
  const auto start = Clock::now();
  const auto training_seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - start).count() -
           eval_seconds;
  };
  double last_log_seconds = 0;
  const int64_t first = trainer.iteration();
  int64_t last_log_iteration = first;
  int last_log_gaussians = trainer.gaussians().size();
  const DensifyOptions& d = o.trainer.densify_options;
  const int64_t densify_end =
      o.trainer.densify
          ? std::min<int64_t>(d.until_iteration, o.trainer.iterations / 2)
          : 0;
  double loss_sum = 0, photometric_sum = 0, mask_sum = 0;
  int64_t counted = 0;  // steps in the sums
  std::vector<double> final_row;
  StageProfile::Get().Start(o.profile);
  while (trainer.iteration() < o.trainer.iterations) {
    const IterationStats s = trainer.Step();
    if (!s.skipped) {  // a skipped step's loss is not finite
      loss_sum += s.loss;
      photometric_sum += s.photometric;
      mask_sum += s.mask;
      ++counted;
    }
    const int64_t it = trainer.iteration();
    const bool log = o.log_every > 0 && it % o.log_every == 0;
    const bool eval = o.eval_every > 0 && it % o.eval_every == 0 &&
                      it < o.trainer.iterations;  // the end is below
    if (log || eval) {
      const double now = training_seconds();
      const int64_t window = it - last_log_iteration;
      const double n = counted > 0 ? counted : NAN;
      StaticMetrics held_out;
      if (eval && lead) {
        const auto eval_start = Clock::now();
        ScopedPass pass(Pass::kEvaluation);
        ScopedStage timer(Stage::kEvaluation);
        held_out = EvaluateHeldOut(trainer, scene);
        eval_seconds +=
            std::chrono::duration<double>(Clock::now() - eval_start).count();
      }
      const GaussianSet& g = trainer.gaussians();
      const std::vector<double> row = {
          loss_sum / n, photometric_sum / n, mask_sum / n,
          static_cast<double>(g.size()),
          static_cast<double>(
              CountDynamic(StaticModel(trainer), o.dynamic_threshold)),
          eval ? held_out.psnr : NAN, eval ? held_out.psnr_water : NAN};
      if (it < o.trainer.iterations) {
        ScopedStage timer(Stage::kCheckpoint);
        history.Add(it, seconds_before + now, row);
        if (lead) history.Write();
      } else {
        final_row = row;  // completed with the final metrics below
      }
      DensifyEtaInput eta;
      eta.iteration = it;
      eta.iterations = o.trainer.iterations;
      eta.seconds_per_iteration =
          (now - last_log_seconds) / std::max<int64_t>(window, 1);
      eta.gaussians = g.size();
      eta.growth_per_iteration =
          static_cast<double>(g.size() - last_log_gaussians) /
          std::max<int64_t>(window, 1);
      eta.densify_end = densify_end;
      eta.max_gaussians = d.max_gaussians;
      std::printf(
          "iter %lld/%d  loss %.5f  gaussians %d  %.1f it/s  ETA %.0f s",
          static_cast<long long>(it), o.trainer.iterations, loss_sum / n,
          g.size(), window / std::max(now - last_log_seconds, 1e-9),
          DensifyingEta(eta));
      if (eval) std::printf("  held-out PSNR %.2f dB", held_out.psnr);
      std::printf("\n");
      std::fflush(stdout);
      last_log_seconds = now;
      last_log_iteration = it;
      last_log_gaussians = g.size();
      loss_sum = photometric_sum = mask_sum = 0;
      counted = 0;
    }
    // Never checkpoint right after a skipped (non-finite) step: the file on
    // disk stays the last good state.
    if (lead && o.checkpoint_every > 0 && it % o.checkpoint_every == 0 &&
        trainer.last_step_ok()) {
      ScopedStage timer(Stage::kCheckpoint);
      WriteCheckpoint(trainer.Save(), checkpoint_path);
    }
  }
  if (trainer.skipped_steps() > 0)
    std::printf("%lld step(s) skipped for a non-finite loss or gradient\n",
                static_cast<long long>(trainer.skipped_steps()));
  if (o.trainer.batch_frames > 1) {
    std::printf("batches of %d frames on %d rank(s); allreduce %.2f MB per "
                "iteration\n",
                o.trainer.batch_frames,
                o.trainer.comm != nullptr ? o.trainer.comm->size() : 1,
                trainer.allreduce_bytes() / 1e6);
  }
  PrintProfileAndStop(
      "es_static, " + std::to_string(trainer.iteration() - first) +
      " iterations, " + std::to_string(trainer.gaussians().size()) +
      " Gaussians at the end");
  StaticStageResult r;
  r.seconds = training_seconds();
  r.iterations_per_second =
      (trainer.iteration() - first) / std::max(r.seconds, 1e-9);

  if (!lead) return r;
  const GaussianSet model = StaticModel(trainer);
  r.test =
      EvaluateStatic(model, scene.frames, scene.test, trainer.render_options());
  r.num_gaussians = model.size();
  r.num_dynamic = CountDynamic(model, o.dynamic_threshold);
  if (final_row.empty() && trainer.iteration() > last_log_iteration) {
    const double w = counted > 0 ? counted : NAN;
    final_row = {loss_sum / w, photometric_sum / w, mask_sum / w,
                 static_cast<double>(r.num_gaussians),
                 static_cast<double>(r.num_dynamic), NAN, NAN};
  }
  if (!final_row.empty()) {
    final_row[5] = r.test.psnr;
    final_row[6] = r.test.psnr_water;
    history.Add(trainer.iteration(), seconds_before + r.seconds, final_row);
  } else {
    history.SetFinalMetrics(trainer.iteration(), seconds_before + r.seconds,
                            {{"psnr_test", r.test.psnr},
                             {"psnr_test_water", r.test.psnr_water}});
  }
  history.Write();
  WritePly(model, o.out_dir + "/static.ply");
  WriteMetrics(r, o.out_dir + "/metrics.json");
  std::printf(
      "test PSNR %.2f dB  SSIM %.4f  water PSNR %.2f  static PSNR "
      "%.2f  mask P/R %.3f/%.3f\n%d Gaussians, %d dynamic; %.1f s "
      "(%.1f it/s); wrote %s/static.ply and metrics.json\n",
      r.test.psnr, r.test.ssim, r.test.psnr_water, r.test.psnr_static,
      r.test.mask_precision, r.test.mask_recall, r.num_gaussians, r.num_dynamic,
      r.seconds, r.iterations_per_second, o.out_dir.c_str());
  return r;
}

}  // namespace es
