#ifndef EULERSPLAT_SOLVERS_POSES_COLMAP_POSES_H_
#define EULERSPLAT_SOLVERS_POSES_COLMAP_POSES_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/io/colmap_io.h"

namespace es {

// COLMAP settings for the frames of one video: one shared camera, a cap on
// SIFT features, matching of neighbours in time (VideoMatchPairs), and
// structure from motion on frames scaled down to sfm_width (the model is
// scaled back to the frames' size) with global bundle adjustment run once
// per growth step instead of until it settles (COLMAP's costliest step;
// measured in docs/results/video.md, "Poses (es_poses)"). One focal
// length: a phone's pixels are square, and a short sweep cannot pin down
// two.
struct PoseOptions {
  std::string colmap = "colmap";  // binary
  std::string camera_model = "SIMPLE_PINHOLE";  // or PINHOLE, SIMPLE_RADIAL
  int sfm_width = 320;     // frames wider than this are matched at this width
  int max_features = 512;  // SIFT features kept per frame
  int overlap = 5;         // each frame is matched with this many successors
  bool upsample = true;    // SIFT's first octave at twice the size
  double global_ba_ratio = 1.5;  // global BA when the model grew this much
  int threads = -1;         // -1: all cores
};

struct PoseReport {
  int frames = 0;       // frames in images/
  int registered = 0;   // frames the kept model has poses for
  int models = 0;       // models the mapper made (the largest is kept)
  int points = 0;
  double mean_reprojection_error_px = 0;  // at the frames' full size
  double scale = 1;     // SfM frame size / frame size
  double extract_seconds = 0, match_seconds = 0, map_seconds = 0;
  double total_seconds = 0;
  // CPU time (user + system) of COLMAP in each step, all threads.
  double extract_cpu_seconds = 0, match_cpu_seconds = 0,
         map_cpu_seconds = 0;
};

// The frame pairs (indices, first < second) to match in a video of
// `frames` frames: each frame with the next `overlap` ones, and with the
// frames 2^k after it for every 2^k > overlap: the wide baselines a slow
// video needs to start the reconstruction from, at a cost of log2(frames)
// pairs per frame instead of all of them.
std::vector<std::pair<int, int>> VideoMatchPairs(int frames, int overlap);

// Recovers the poses of the frames in scene_dir/images (image files, one
// size) with COLMAP and writes the largest model as text into out_dir,
// which must not exist yet. Calls progress(line) at each step. Throws
// InputError naming the step and quoting COLMAP's log when a step fails or
// nothing is registered.
PoseReport RecoverPoses(const std::string& scene_dir,
                        const std::string& out_dir,
                        const PoseOptions& options,
                        const std::function<void(const std::string&)>&
                            progress = nullptr);

// A model found on frames scaled by (sx, sy) expressed at the frames' full
// size: intrinsics, image size, 2D points and reprojection errors scaled by
// 1 / s. Supports PINHOLE, SIMPLE_PINHOLE, SIMPLE_RADIAL and RADIAL.
void RescaleColmapModel(double sx, double sy, int width, int height,
                        ColmapModel* model);

// Mean reprojection error over all observations (each point's error
// weighted by its track length), in pixels; 0 for an empty model.
double MeanReprojectionError(const ColmapModel& model);

// The report as a JSON object (pose_report.json).
nlohmann::ordered_json PoseReportJson(const PoseReport& report);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_POSES_COLMAP_POSES_H_
