// Water masks from the video itself (no segmentation network): regions
// where a static model fitted without masks cannot explain the frames, by
// non-rigid optical flow and by how its misfit changes over time, then
// within them per pixel, where the water's share of the colour is over
// one half (with a margin), plus the calm water joined to them that is
// water-coloured in every frame (core/masks/water_masks.h,
// water_matting.h). Writes one PNG per registered frame (same names as the
// images, .png; white = water) that a person can inspect and edit, a sheet
// to check them with, and a report; with --truth also the IoU, precision
// and recall against true masks.
//
//   es_masks --scene DIR --static static.ply --out MASKS_DIR
//            [--sheet FILE] [--report FILE] [--truth TRUE_MASKS_DIR]

#include <cstdio>
#include <filesystem>
#include <string>

#include <gflags/gflags.h>
#include <opencv2/imgproc.hpp>

#include "apps/common/app_main.h"
#include "core/base/atomic_file.h"
#include "core/io/frame_loading.h"
#include "core/io/image_file.h"
#include "core/io/json_file.h"
#include "core/base/input_error.h"
#include "core/io/ply_io.h"
#include "core/io/scene.h"
#include "core/masks/mask_scores.h"
#include "core/masks/water_masks.h"

DEFINE_string(scene, "", "Scene directory (images/, sparse/0/).");
DEFINE_string(static, "", "Static model fitted without masks (PLY).");
DEFINE_string(out, "", "Mask folder to write (must not exist; written "
              "complete or not at all). Nothing is written when no water "
              "is found.");
DEFINE_string(sheet, "", "Check sheet PNG (default: OUT_sheet.png).");
DEFINE_string(report, "", "Report JSON (default: OUT_report.json).");
DEFINE_string(truth, "", "Optional true masks (same names): adds the mean "
              "per-frame IoU, precision and recall to the report.");
DEFINE_double(image_scale, 1.0, "Work at this fraction of the frames' size "
              "(masks are written at full size).");
DEFINE_int32(window, 2, "Frames on each side for temporal averaging and "
             "voting.");
DEFINE_int32(change_gap, 4, "Video frames between the frames whose "
             "residuals against the static model are compared (3 on each "
             "side: gap, 2 gap, 3 gap); a few frames, so that water has "
             "changed (raise it for a high frame rate).");
DEFINE_string(cues, "flow,change,misfit", "Cues the evidence takes, "
              "comma-separated: flow (optical flow the camera's motion does "
              "not explain), change (misfit that changes over time at a "
              "surface point), misfit (a surface unlike the static fit's); "
              "fewer, to measure what each brings.");
DEFINE_int32(change_tolerance, 1, "Pixels of misregistration forgiven "
             "when frames carried by the camera's motion are compared (fine "
             "static texture must not look changed); 0: pixel to pixel.");
DEFINE_double(misfit_blur, 0, "The misfit cue blurs the residual over "
              "this radius (fraction of the width) first, so fine texture "
              "that a short fit renders as its average is no misfit; 0: per "
              "pixel.");
DEFINE_bool(flow_needs_change, false, "The flow cue counts only as far as "
            "the camera's motion fails to explain the next frame's colours "
            "(optical flow goes wrong on fine repeating texture).");
DEFINE_double(min_score, 2.0, "Evidence (in units of the static region's "
              "level) below which nothing is water.");
DEFINE_double(min_water_fraction, 0.02, "Mean water fraction below which "
              "the scene is called static (no masks written).");
DEFINE_bool(matting, true, "Within the water regions, keep only the "
            "pixels whose colour is more water than the scenery seen there "
            "at other times (false: the smooth regions are the masks).");
DEFINE_bool(calm_water, true, "With --matting, also the pixels beyond the "
            "regions whose colour is water's in every frame and that "
            "connect to the water found (a calm pool next to a fall); "
            "false: only near the regions.");
DEFINE_bool(white_background, false, "The static model was trained on "
            "white.");

namespace {

namespace fs = std::filesystem;

// The size of the scene's frames as stored (masks must match it).
cv::Size StoredSize(const es::Scene& scene) {
  cv::Size size;
  es::ForEachFrameImage(
      (fs::path(scene.dir) / "images").string(),
      {scene.frames[0].camera.image_name},
      [&size](int, const cv::Mat& image, const std::string&) {
        size = image.size();
      });
  return size;
}

std::string MaskName(const std::string& image_name) {
  return fs::path(image_name).replace_extension(".png").string();
}

void WriteMasks(const es::Scene& scene, const es::WaterMaskResult& result,
                const fs::path& out) {
  const cv::Size size = StoredSize(scene);
  const fs::path staging = out.string() + ".partial";
  fs::remove_all(staging);
  for (size_t i = 0; i < scene.frames.size(); ++i) {
    const fs::path path =
        staging / MaskName(scene.frames[i].camera.image_name);
    fs::create_directories(path.parent_path());
    cv::Mat mask;
    cv::resize(result.masks[i], mask, size, 0, 0, cv::INTER_LINEAR);
    cv::threshold(mask, mask, 127, 255, cv::THRESH_BINARY);
    es::WriteImageAtomically(path.string(), mask);
  }
  fs::rename(staging, out);
}

// Mean per-frame scores against the masks in truth_dir (read at the
// working size).
es::MaskScore ScoreAgainst(const es::Scene& scene,
                           const es::WaterMaskResult& result,
                           const std::string& truth_dir) {
  std::vector<std::string> names;
  for (const es::Frame& f : scene.frames) names.push_back(f.camera.image_name);
  std::vector<cv::Mat> truths;
  for (const std::string& file : es::FindMaskFiles(truth_dir, names)) {
    truths.emplace_back();
    cv::resize(es::ReadMask(file), truths.back(), result.masks[0].size(), 0,
               0, cv::INTER_AREA);
  }
  return es::MeanMaskScore(result.masks, truths);
}

int Main() {
  if (FLAGS_scene.empty() || FLAGS_static.empty() || FLAGS_out.empty())
    throw es::InputError("--scene, --static and --out are required");
  if (fs::exists(FLAGS_out))
    throw es::InputError(FLAGS_out + ": exists; masks are only written to a "
                         "new folder (delete it to redo)");
  if (FLAGS_window < 0) throw es::InputError("--window must be >= 0");
  if (FLAGS_change_gap < 1)
    throw es::InputError("--change_gap must be >= 1");
  if (FLAGS_change_tolerance < 0)
    throw es::InputError("--change_tolerance must be >= 0");
  if (!(FLAGS_misfit_blur >= 0))
    throw es::InputError("--misfit_blur must be >= 0");
  const es::WaterCues cues = es::ParseWaterCues(FLAGS_cues);
  const std::string sheet =
      FLAGS_sheet.empty() ? FLAGS_out + "_sheet.png" : FLAGS_sheet;
  const std::string report =
      FLAGS_report.empty() ? FLAGS_out + "_report.json" : FLAGS_report;
  es::SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const es::Scene scene = es::LoadScene(FLAGS_scene, scene_options);
  const es::GaussianSet model = es::ReadPly(FLAGS_static);

  es::WaterMaskOptions options;
  options.window = FLAGS_window;
  options.min_score = FLAGS_min_score;
  options.change.gap = FLAGS_change_gap;
  options.change.tolerance = FLAGS_change_tolerance;
  options.cues = cues;
  options.misfit_blur = FLAGS_misfit_blur;
  options.flow_needs_change = FLAGS_flow_needs_change;
  options.min_water_fraction = FLAGS_min_water_fraction;
  options.matting = FLAGS_matting;
  options.matting_options.calm_water = FLAGS_calm_water;
  if (FLAGS_white_background) options.render.background.setOnes();
  std::printf("[masks] %zu frames at %dx%d: residual change over time, "
              "optical flow vs camera motion, then the water's share of "
              "each pixel\n",
              scene.frames.size(), scene.frames[0].image.cols,
              scene.frames[0].image.rows);
  const es::WaterMaskResult result = es::EstimateWaterMasks(
      scene, model, options, [](int done, int total) {
        if (done % 10 == 0 || done == total) {
          std::printf("[masks] step %d / %d (cues, then matting, per "
                      "frame)\n", done, total);
          std::fflush(stdout);
        }
      });
  es::WriteImageAtomically(sheet, es::WaterMaskSheet(scene, result, 8));
  nlohmann::ordered_json json;
  json["frames"] = scene.frames.size();
  json["has_water"] = result.has_water;
  json["water_fraction"] = result.water_fraction;
  json["threshold"] = result.threshold;
  json["mean_iou"] = nullptr;
  if (!FLAGS_truth.empty()) {
    const es::MaskScore score = ScoreAgainst(scene, result, FLAGS_truth);
    json["mean_iou"] = score.iou;
    json["mean_precision"] = score.precision;
    json["mean_recall"] = score.recall;
    json["truth"] = FLAGS_truth;
  }
  // The report last: its presence means the masks are complete.
  if (result.has_water) WriteMasks(scene, result, FLAGS_out);
  es::WriteJsonFile(report, json);

  std::printf("[masks] water covers %.1f%% of the frames (threshold %.2f x "
              "the static level)%s\n",
              100 * result.water_fraction, result.threshold,
              result.has_water ? "" : ": nothing moves, no masks written");
  if (!FLAGS_truth.empty())
    std::printf("[masks] vs %s: mean IoU %.3f, precision %.3f, recall "
                "%.3f\n", FLAGS_truth.c_str(),
                json["mean_iou"].get<double>(),
                json["mean_precision"].get<double>(),
                json["mean_recall"].get<double>());
  std::printf("[masks] check sheet %s%s%s\n", sheet.c_str(),
              result.has_water ? ", masks " : "",
              result.has_water ? FLAGS_out.c_str() : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Finds water masks from the video (no network).\n"
                    "  es_masks --scene DIR --static static.ply --out DIR",
                    Main);
}
