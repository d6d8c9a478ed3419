// Recovers camera poses for the frames of one video with COLMAP, with
// settings for video: one shared camera, a cap on SIFT features per frame,
// sequential matching, structure from motion at a reduced width (the model
// is scaled back to the frames' size). Prints and writes
// OUT/pose_report.json: frames registered of all, mean reprojection error,
// time per step. Frames COLMAP does not register are left out of the model;
// LoadScene keeps every frame's place in time from its name.
//
//   es_poses --scene DIR [--out DIR/sparse/0] [--sfm_width 320]
//            [--max_features 1024] [--overlap 10]

#include <cstdio>
#include <filesystem>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/colmap_poses.h"
#include "core/io/atomic_file.h"
#include "core/io/input_error.h"

DEFINE_string(scene, "", "Scene directory whose images/ holds the frames "
              "(png/jpg, time order = name order).");
DEFINE_string(out, "", "Output model folder (default SCENE/sparse/0); must "
              "not exist, so exact poses are never overwritten.");
DEFINE_int32(sfm_width, 320, "Frames wider than this are matched and "
             "reconstructed at this width (0: full size); the model is "
             "scaled back.");
DEFINE_int32(max_features, 1024, "SIFT features kept per frame.");
DEFINE_int32(overlap, 10, "Each frame is matched with this many following "
             "frames (sequential matching).");
DEFINE_string(camera_model, "PINHOLE", "PINHOLE or SIMPLE_RADIAL (one "
              "camera shared by all frames).");
DEFINE_int32(threads, -1, "COLMAP threads (-1: all cores).");
DEFINE_string(colmap, "colmap", "COLMAP binary.");

namespace {

int Main() {
  if (FLAGS_scene.empty()) throw es::InputError("--scene is required");
  const std::string out = FLAGS_out.empty()
                              ? (std::filesystem::path(FLAGS_scene) /
                                 "sparse" / "0").string()
                              : FLAGS_out;
  es::PoseOptions options;
  options.colmap = FLAGS_colmap;
  options.camera_model = FLAGS_camera_model;
  options.sfm_width = FLAGS_sfm_width;
  options.max_features = FLAGS_max_features;
  options.overlap = FLAGS_overlap;
  options.threads = FLAGS_threads;
  const es::PoseReport r =
      es::RecoverPoses(FLAGS_scene, out, options, [](const std::string& s) {
        std::printf("[poses] %s\n", s.c_str());
        std::fflush(stdout);
      });
  es::WriteTextFileAtomically(out + "/pose_report.json",
                              es::PoseReportJson(r));
  std::printf("[poses] registered %d of %d frames (%.1f%%, largest of %d "
              "models), %d points, mean reprojection error %.2f px; "
              "%.0f s (extract %.0f, match %.0f, map %.0f) -> %s\n",
              r.registered, r.frames, 100.0 * r.registered / r.frames,
              r.models, r.points, r.mean_reprojection_error_px,
              r.total_seconds, r.extract_seconds, r.match_seconds,
              r.map_seconds, out.c_str());
  if (r.registered < r.frames) {
    std::printf("[poses] %d frame(s) not registered: left out of training, "
                "the others keep their place in time\n",
                r.frames - r.registered);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(argc, argv,
                    "Recovers camera poses of a video's frames with COLMAP.\n"
                    "  es_poses --scene DIR [--out DIR/sparse/0]",
                    Main);
}
