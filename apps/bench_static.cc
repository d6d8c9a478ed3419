// Stage-1 benchmark: iterations per second and held-out PSNR against
// training wall time, on the default scene.
//
//   build/bin/bench_static --scene out/default_scene --iterations 3000
//                          --eval_every 250 [--image_scale 1] [--csv FILE]
//
// Trains exactly as es_static does with its defaults (same scene loading,
// seeding and StaticTrainer); only the knobs below are flags. Checkpoint
// evaluations on the held-out split run outside the timed clock.

#include <gflags/gflags.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "apps/common/app_main.h"
#include "core/base/atomic_file.h"
#include "core/io/csv_table.h"
#include "core/base/input_error.h"
#include "solvers/train/static_stage.h"

constexpr char kUsage[] =
    "Stage-1 benchmark: held-out PSNR / SSIM (full, water, static region) "
    "against training wall time.\n"
    "  bench_static --scene out/default_scene --iterations 3000 "
    "--eval_every 250 [--csv FILE]";

DEFINE_string(scene, "out/default_scene",
              "Scene directory (images/, masks/, sparse/0/); "
              "scripts/run_default.sh generates the default one.");
DEFINE_int32(iterations, 3000,
             "Training iterations (also sets the position learning-rate "
             "decay, as es_static --iterations does).");
DEFINE_int32(eval_every, 250,
             "Evaluate the held-out split every this many iterations (and "
             "at 0 and the end), outside the timed clock.");
DEFINE_double(image_scale, 1.0, "Resize frames (and intrinsics) by this.");
DEFINE_uint64(seed, 0, "Seed for frame sampling and splitting.");
DEFINE_double(densify_grad_threshold, 2e-4,
              "Mean view-space (NDC) gradient norm that triggers clone/split "
              "(es_static's flag of the same name).");
DEFINE_string(csv, "", "Also write the table to this CSV file.");

namespace es {
namespace {

struct Row {
  int iteration = 0;
  double train_seconds = 0;
  double iterations_per_second = 0;  // over the interval since the last row
  int gaussians = 0;
  StaticMetrics test;
};

void PrintRow(const Row& r) {
  std::printf("%9d %9.2f %8.1f %9d %8.2f %8.2f %8.2f %7.4f\n", r.iteration,
              r.train_seconds, r.iterations_per_second, r.gaussians,
              r.test.psnr, r.test.psnr_water, r.test.psnr_static, r.test.ssim);
  std::fflush(stdout);
}

void WriteCsv(const std::vector<Row>& rows, const std::string& path) {
  CsvTable table;
  table.columns = {"iteration",  "train_seconds", "iterations_per_second",
                   "gaussians",  "psnr",          "psnr_water",
                   "psnr_static", "ssim"};
  for (const Row& r : rows) {
    table.rows.push_back({static_cast<double>(r.iteration), r.train_seconds,
                          r.iterations_per_second,
                          static_cast<double>(r.gaussians), r.test.psnr,
                          r.test.psnr_water, r.test.psnr_static, r.test.ssim});
  }
  WriteTextFileAtomically(path, CsvText(table));
}

int Run() {
  if (!std::filesystem::is_directory(FLAGS_scene))
    throw InputError("--scene " + FLAGS_scene +
                     ": no such directory; run scripts/run_default.sh first "
                     "to generate the default scene (out/default_scene)");
  if (FLAGS_iterations <= 0) throw InputError("--iterations must be positive");
  if (FLAGS_eval_every <= 0) throw InputError("--eval_every must be positive");
  if (FLAGS_densify_grad_threshold <= 0)
    throw InputError("--densify_grad_threshold must be > 0");

  SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const Scene scene = LoadStaticScene(FLAGS_scene, scene_options);
  StaticTrainerOptions options;
  options.iterations = FLAGS_iterations;
  options.seed = FLAGS_seed;
  options.densify_options.grad_threshold = FLAGS_densify_grad_threshold;
  const std::unique_ptr<StaticTrainer> trainer =
      MakeStaticTrainer(scene, options);

  const Camera& camera = scene.frames[scene.train[0]].camera;
  std::printf(
      "%s: %zu train / %zu test frames at %dx%d, %zu points, %d threads\n",
      FLAGS_scene.c_str(), scene.train.size(), scene.test.size(), camera.width,
      camera.height, scene.points.size(), omp_get_max_threads());
  std::printf("%9s %9s %8s %9s %8s %8s %8s %7s\n", "iteration", "train_s",
              "it/s", "gaussians", "psnr", "water", "static", "ssim");

  using Clock = std::chrono::steady_clock;
  std::vector<Row> rows;
  Row row;
  row.gaussians = trainer->gaussians().size();
  row.test = EvaluateHeldOut(*trainer, scene);
  rows.push_back(row);
  PrintRow(row);
  double train_seconds = 0;
  while (trainer->iteration() < FLAGS_iterations) {
    const int begin = static_cast<int>(trainer->iteration());
    const int end = std::min(FLAGS_iterations, begin + FLAGS_eval_every);
    const auto start = Clock::now();
    while (trainer->iteration() < end) trainer->Step();
    const double dt =
        std::chrono::duration<double>(Clock::now() - start).count();
    train_seconds += dt;
    row.iteration = end;
    row.train_seconds = train_seconds;
    row.iterations_per_second = (end - begin) / std::max(dt, 1e-9);
    row.gaussians = trainer->gaussians().size();
    row.test = EvaluateHeldOut(*trainer, scene);
    rows.push_back(row);
    PrintRow(row);
  }
  std::printf("mean %.1f it/s over %d iterations (%.1f s of training)\n",
              FLAGS_iterations / std::max(train_seconds, 1e-9),
              FLAGS_iterations, train_seconds);
  if (!FLAGS_csv.empty()) WriteCsv(rows, FLAGS_csv);
  return 0;
}

}  // namespace
}  // namespace es

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, es::Run);
}
