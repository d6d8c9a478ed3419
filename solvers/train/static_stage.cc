#include "solvers/train/static_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/io/input_error.h"
#include "core/io/ply_io.h"
#include "core/model/gaussian_init.h"
#include "core/profile/stage_profile.h"
#include "solvers/checkpoint/checkpoint.h"

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
  if (!(o.dynamic_threshold > 0 && o.dynamic_threshold < 1))
    fail("--dynamic_threshold must be in (0, 1)");
  const DensifyOptions& d = t.densify_options;
  if (d.interval <= 0) fail("--densify_interval must be positive");
  if (d.max_gaussians <= 0) fail("--max_gaussians must be positive");
  if (d.grad_threshold <= 0) fail("--densify_grad_threshold must be > 0");
}

std::string Json(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

void WriteMetrics(const StaticStageResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << "{\n"
      << "  \"psnr_test\": " << Json(r.test.psnr) << ",\n"
      << "  \"ssim_test\": " << Json(r.test.ssim) << ",\n"
      << "  \"psnr_test_water\": " << Json(r.test.psnr_water) << ",\n"
      << "  \"ssim_test_water\": " << Json(r.test.ssim_water) << ",\n"
      << "  \"psnr_test_static\": " << Json(r.test.psnr_static) << ",\n"
      << "  \"ssim_test_static\": " << Json(r.test.ssim_static) << ",\n"
      << "  \"num_gaussians\": " << r.num_gaussians << ",\n"
      << "  \"num_dynamic\": " << r.num_dynamic << ",\n"
      << "  \"seconds\": " << Json(r.seconds) << ",\n"
      << "  \"iterations_per_second\": " << Json(r.iterations_per_second)
      << ",\n"
      << "  \"mask_precision\": " << Json(r.test.mask_precision) << ",\n"
      << "  \"mask_recall\": " << Json(r.test.mask_recall) << "\n"
      << "}\n";
  if (!out) throw InputError(path + ": write failed");
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

std::unique_ptr<StaticTrainer> MakeStaticTrainer(
    const Scene& scene, const StaticTrainerOptions& options) {
  return std::make_unique<StaticTrainer>(
      &scene.frames, scene.train, options,
      InitGaussiansFromPoints(scene.points, scene.point_colors, 0));
}

GaussianSet StaticModel(const StaticTrainer& trainer) {
  GaussianSet model = trainer.gaussians();
  if (!trainer.uses_masks())
    std::fill(model.dynamic_logits.begin(), model.dynamic_logits.end(),
              Logit(kStaticProbability));
  return model;
}

StaticMetrics EvaluateHeldOut(const StaticTrainer& trainer,
                              const Scene& scene) {
  return EvaluateStatic(StaticModel(trainer), scene.frames, scene.test,
                        trainer.render_options());
}

StaticStageResult RunStaticStage(const StaticStageOptions& o) {
  Validate(o);
  const std::string checkpoint_path = o.out_dir + "/checkpoint.bin";
  Checkpoint checkpoint;
  if (o.resume) checkpoint = ReadCheckpoint(checkpoint_path);
  const Scene scene = LoadStaticScene(o.scene_dir, o.scene);
  std::filesystem::create_directories(o.out_dir);

  const std::unique_ptr<StaticTrainer> trainer_owner =
      MakeStaticTrainer(scene, o.trainer);
  StaticTrainer& trainer = *trainer_owner;
  if (o.resume) {
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

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_log = start;
  const int64_t first = trainer.iteration();
  int64_t last_log_iteration = first;
  double loss_sum = 0;
  StageProfile::Get().Start(o.profile);
  while (trainer.iteration() < o.trainer.iterations) {
    const IterationStats s = trainer.Step();
    if (!s.skipped) loss_sum += s.loss;
    const int64_t it = trainer.iteration();
    if (o.log_every > 0 && it % o.log_every == 0) {
      const auto now = Clock::now();
      const double dt = std::chrono::duration<double>(now - last_log).count();
      const double rate = (it - last_log_iteration) / std::max(dt, 1e-9);
      const double eta = (o.trainer.iterations - it) / std::max(rate, 1e-9);
      std::printf(
          "iter %lld/%d  loss %.5f  gaussians %d  %.1f it/s  "
          "ETA %.0f s\n",
          static_cast<long long>(it), o.trainer.iterations,
          loss_sum / (it - last_log_iteration), trainer.gaussians().size(),
          rate, eta);
      std::fflush(stdout);
      last_log = now;
      last_log_iteration = it;
      loss_sum = 0;
    }
    // Never checkpoint right after a skipped (non-finite) step: the file on
    // disk stays the last good state.
    if (o.checkpoint_every > 0 && it % o.checkpoint_every == 0 &&
        trainer.last_step_ok())
      WriteCheckpoint(trainer.Save(), checkpoint_path);
  }
  if (trainer.skipped_steps() > 0)
    std::printf("%lld step(s) skipped for a non-finite loss or gradient\n",
                static_cast<long long>(trainer.skipped_steps()));
  StageProfile::Get().PrintAndStop(
      "es_static, " + std::to_string(trainer.iteration() - first) +
      " iterations, " + std::to_string(trainer.gaussians().size()) +
      " Gaussians at the end");
  StaticStageResult r;
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.iterations_per_second =
      (trainer.iteration() - first) / std::max(r.seconds, 1e-9);

  const GaussianSet model = StaticModel(trainer);
  r.test =
      EvaluateStatic(model, scene.frames, scene.test, trainer.render_options());
  r.num_gaussians = model.size();
  for (double logit : model.dynamic_logits)
    r.num_dynamic += Sigmoid(logit) > o.dynamic_threshold;
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
