// Recovers camera poses for the frames of one video with COLMAP, with
// settings for video: one shared camera, a cap on SIFT features per frame,
// matching of neighbours in time (plus frames 2^k apart), structure from
// motion at a reduced width (the model is scaled back to the frames' size)
// with rare global bundle adjustment. Prints and writes
// OUT/pose_report.json: frames registered of all, mean reprojection error,
// wall and CPU time per step, and with --truth the error against known
// poses. Frames COLMAP does not register are left out of the model;
// LoadScene keeps every frame's place in time from its name.
//
//   es_poses --scene DIR [--out DIR/sparse/0] [--sfm_width 320]
//            [--max_features 512] [--overlap 5] [--truth MODEL_DIR]

#include <cstdio>
#include <filesystem>

#include <gflags/gflags.h>
#include <omp.h>

#include "apps/common/app_main.h"
#include "solvers/poses/colmap_poses.h"
#include "solvers/poses/pose_accuracy.h"
#include "core/base/input_error.h"
#include "core/io/json_file.h"

constexpr char kUsage[] =
    "Recovers camera poses of a video's frames with COLMAP.\n"
    "  es_poses --scene DIR [--out DIR/sparse/0]";

DEFINE_string(scene, "", "Scene directory whose images/ holds the frames "
              "(png/jpg, time order = name order).");
DEFINE_string(out, "", "Output model folder (default SCENE/sparse/0); must "
              "not exist, so exact poses are never overwritten.");
DEFINE_int32(sfm_width, 320, "Frames wider than this are matched and "
             "reconstructed at this width (0: full size); the model is "
             "scaled back.");
DEFINE_int32(max_features, 512, "SIFT features kept per frame.");
DEFINE_int32(overlap, 5, "Each frame is matched with this many following "
             "frames, and with the frames 2^k after it beyond those.");
DEFINE_bool(upsample, true, "SIFT starts at twice the SfM size (more, "
            "better-placed features on small frames; slower).");
DEFINE_double(global_ba_ratio, 1.5, "Global bundle adjustment whenever the "
              "model has grown by this factor (and once at the end).");
DEFINE_string(camera_model, "SIMPLE_PINHOLE", "SIMPLE_PINHOLE (one focal "
              "length), PINHOLE or SIMPLE_RADIAL; one camera shared by all "
              "frames.");
DEFINE_string(colmap, "colmap", "COLMAP binary.");
DEFINE_string(truth, "", "Optional folder of known poses (COLMAP model, "
              "e.g. an es_synth scene's sparse/0): the report adds the "
              "camera position and rotation error after a similarity "
              "alignment.");

namespace {

int Main() {
  if (FLAGS_scene.empty()) throw es::InputError("--scene is required");
  const std::string out = FLAGS_out.empty()
                              ? (std::filesystem::path(FLAGS_scene) /
                                 "sparse" / "0").string()
                              : FLAGS_out;
  // Read first: a wrong --truth should fail before minutes of COLMAP.
  const es::ColmapModel truth = FLAGS_truth.empty()
                                    ? es::ColmapModel()
                                    : es::ReadColmapModel(FLAGS_truth);
  es::PoseOptions options;
  options.colmap = FLAGS_colmap;
  options.camera_model = FLAGS_camera_model;
  options.sfm_width = FLAGS_sfm_width;
  options.max_features = FLAGS_max_features;
  options.overlap = FLAGS_overlap;
  options.upsample = FLAGS_upsample;
  options.global_ba_ratio = FLAGS_global_ba_ratio;
  options.threads = omp_get_max_threads();  // --threads, resolved
  const es::PoseReport r =
      es::RecoverPoses(FLAGS_scene, out, options, [](const std::string& s) {
        std::printf("[poses] %s\n", s.c_str());
        std::fflush(stdout);
      });
  nlohmann::ordered_json json = es::PoseReportJson(r);
  std::printf("[poses] registered %d of %d frames (%.1f%%, largest of %d "
              "models), %d points, mean reprojection error %.2f px\n"
              "[poses] %.0f s (extract %.0f, match %.0f, map %.0f); COLMAP "
              "CPU time %.0f s (extract %.0f, match %.0f, map %.0f) -> %s\n",
              r.registered, r.frames, 100.0 * r.registered / r.frames,
              r.models, r.points, r.mean_reprojection_error_px,
              r.total_seconds, r.extract_seconds, r.match_seconds,
              r.map_seconds,
              r.extract_cpu_seconds + r.match_cpu_seconds + r.map_cpu_seconds,
              r.extract_cpu_seconds, r.match_cpu_seconds, r.map_cpu_seconds,
              out.c_str());
  if (!FLAGS_truth.empty()) {
    const es::PoseAccuracy a =
        es::ComparePoses(es::ReadColmapModel(out), truth);
    json["truth"] = FLAGS_truth;
    json["compared"] = a.compared;
    json["position_rmse"] = a.position_rmse;
    json["position_rmse_relative"] = a.position_rmse_relative;
    json["mean_rotation_error_deg"] = a.mean_rotation_error_deg;
    json["max_rotation_error_deg"] = a.max_rotation_error_deg;
    std::printf("[poses] vs %s (%d frames, after a similarity alignment): "
                "position RMSE %.4f (%.2f%% of the trajectory's extent), "
                "rotation error mean %.3f / max %.3f deg\n",
                FLAGS_truth.c_str(), a.compared, a.position_rmse,
                100 * a.position_rmse_relative, a.mean_rotation_error_deg,
                a.max_rotation_error_deg);
  }
  es::WriteJsonFile(out + "/pose_report.json", json);
  if (r.registered < r.frames) {
    std::printf("[poses] %d frame(s) not registered: left out of training, "
                "the others keep their place in time\n",
                r.frames - r.registered);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, Main);
}
