// Measures a second video of a scene against the scene's own, with the
// figures es_eval reports for a model: held-out PSNR / SSIM (whole frame and
// water) and realism (detail, motion, distribution distances). Made for
// calibrating those figures: `es_synth --water_seed` re-draws a synthetic
// scene's stochastic water with the same scenery and cameras, and that
// independent realization is what a model that gets the water's statistics
// exactly right, but not its individual droplets, would score.
//
//   es_compare --scene DIR --other DIR --out DIR

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/flag_checks.h"
#include "apps/common/realism_flags.h"
#include "apps/common/scaled_scene.h"
#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/io/output_dir.h"
#include "core/io/scene.h"
#include "solvers/eval/eval_report.h"
#include "solvers/eval/loop_evaluation.h"
#include "solvers/eval/realism_evaluation.h"

constexpr char kUsage[] =
    "Measures another video of a scene (same cameras) "
    "against the scene's frames, as es_eval measures a "
    "model.\n"
    "  es_compare --scene DIR --other DIR --out DIR\n"
    "Writes OUT/compare.json (held-out PSNR / SSIM, "
    "realism).";

DEFINE_string(scene, "", "Scene directory whose frames, masks and split are "
              "the reference.");
DEFINE_string(other, "", "Scene directory with the video to measure: the "
              "same number of frames, image size and cameras (e.g. "
              "es_synth with the same flags and another --water_seed).");
DEFINE_string(out, "", "Output directory for compare.json (created).");
DEFINE_double(image_scale, 1.0, "Compare at this fraction of the image "
              "size (es_eval's --image_scale of the runs to set beside).");
DEFINE_int32(compare_frames, 4, "Frames written to OUT/compare/ (other "
             "left, scene right) to look at; 0: none.");

namespace {

// Camera centres further apart than this fraction of the path's extent
// mean the two videos were not filmed along the same path.
constexpr double kCameraTolerance = 1e-6;

void CheckSameCameras(const es::Scene& scene, const es::Scene& other) {
  if (scene.frames.size() != other.frames.size()) {
    throw es::InputError(
        FLAGS_other + ": " + std::to_string(other.frames.size()) +
        " frames, but " + FLAGS_scene + " has " +
        std::to_string(scene.frames.size()));
  }
  double extent = 0;
  for (const es::Frame& f : scene.frames) {
    extent = std::max(extent, (f.camera.Center() -
                               scene.frames[0].camera.Center()).norm());
  }
  const double tolerance = kCameraTolerance * std::max(extent, 1.0);
  for (size_t i = 0; i < scene.frames.size(); ++i) {
    const es::Camera& a = scene.frames[i].camera;
    const es::Camera& b = other.frames[i].camera;
    if (a.width != b.width || a.height != b.height) {
      throw es::InputError(FLAGS_other + ": frame " + std::to_string(i) +
                           " is " + std::to_string(b.width) + "x" +
                           std::to_string(b.height) + ", not " +
                           std::to_string(a.width) + "x" +
                           std::to_string(a.height));
    }
    if ((a.Center() - b.Center()).norm() > tolerance ||
        !a.R().isApprox(b.R(), 1e-6)) {
      throw es::InputError(FLAGS_other + ": frame " + std::to_string(i) +
                           "'s camera differs from " + FLAGS_scene +
                           "'s (the videos must share their cameras)");
    }
  }
}

std::vector<cv::Mat> AsDouble(const std::vector<es::Frame>& frames) {
  std::vector<cv::Mat> images;
  for (const es::Frame& f : frames) {
    cv::Mat x;
    f.image.convertTo(x, CV_64F);
    images.push_back(x);
  }
  return images;
}

int Run() {
  es::RequireFlag("scene", FLAGS_scene);
  es::RequireFlag("other", FLAGS_other);
  es::RequireFlag("out", FLAGS_out);
  es::RequirePositive("image_scale", FLAGS_image_scale);
  es::RequireAtLeast("compare_frames", FLAGS_compare_frames, 0);
  const es::RealismOptions options = es::RealismOptionsFromFlags();
  es::PrepareOutputDirectory(FLAGS_out, "out");
  const es::Scene scene = es::LoadScaledScene(FLAGS_scene, FLAGS_image_scale);
  const es::Scene other = es::LoadScaledScene(FLAGS_other, FLAGS_image_scale);
  CheckSameCameras(scene, other);
  if (scene.test.empty()) {
    throw es::InputError(FLAGS_scene + ": no held-out frames (see "
                         "split.txt)");
  }
  const std::vector<cv::Mat> images = AsDouble(other.frames);
  std::vector<cv::Mat> held_out;
  for (int i : scene.test) held_out.push_back(images[i]);
  const es::LoopMetrics metrics =
      es::CompareWithFrames(held_out, scene.frames, scene.test);
  const es::RealismMetrics realism =
      es::EvaluateRealism(images, scene.frames, options);
  if (FLAGS_compare_frames > 0) {
    es::WriteComparisonFrames(images, scene.frames, FLAGS_compare_frames,
                              FLAGS_out + "/compare");
  }

  const nlohmann::ordered_json json = {
      {"scene", FLAGS_scene},
      {"other", FLAGS_other},
      {"held_out", es::HeldOutJson(metrics)},
      {"realism", es::RealismJson(realism)}};
  const std::string path = FLAGS_out + "/compare.json";
  es::WriteJsonFile(path, json);
  std::printf("%s against %s (%zu frames)\n", FLAGS_other.c_str(),
              FLAGS_scene.c_str(), scene.frames.size());
  es::PrintHeldOutRows(metrics, scene.has_masks);
  std::printf("  realism (ratios: 1 = like the scene; distance: 0 = same "
              "statistics)\n");
  es::PrintRealismRow("  water", realism.water);
  es::PrintRealismRow("  static (control)", realism.static_region);
  es::PrintRealismRow("  whole frame", realism.frame);
  std::printf("wrote %s\n", path.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, Run);
}
