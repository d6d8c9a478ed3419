#ifndef EULERSPLAT_CORE_IO_SCENE_H_
#define EULERSPLAT_CORE_IO_SCENE_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/model/camera.h"

namespace es {

// One video frame with its (pinhole, undistorted) camera.
struct Frame {
  Camera camera;
  cv::Mat image;  // CV_32FC3, RGB order, values in [0, 1]
  cv::Mat mask;   // CV_32FC1 in [0, 1] (1 = water); empty if the scene has none
  // Position in the video (0 = its first frame). Frames COLMAP did not
  // register are not loaded but keep their place, so this can skip numbers;
  // the loop's cycle index and cycle number come from it, never from the
  // frame's place in Scene::frames.
  int time_index = 0;
};

struct SceneOptions {
  double image_scale = 1.0;  // resize frames (and intrinsics) by this factor
  int num_test_segments = 3; // default held-out split: this many segments
  double test_fraction = 0.1;  // of all frames, spread over those segments
};

// A scene directory (see docs/DESIGN.md): images/ (or a video file in it),
// masks/, sparse/0/, optional split.txt (format in core/io/split.h). Frames
// are sorted by image name, which is their time order; a frame's time_index
// is its position among all frames of images/ (or its number in the video),
// whether or not COLMAP registered the others.
struct Scene {
  std::string dir;
  std::vector<Frame> frames;
  std::vector<int> train;  // indices into frames
  std::vector<int> test;
  std::vector<Eigen::Vector3d> points;  // points3D positions
  std::vector<Eigen::Vector3d> point_colors;  // in [0, 1]
  bool has_masks = false;
};

// Loads and validates a scene; throws InputError naming the file and the
// problem (missing images are all listed by name).
Scene LoadScene(const std::string& dir, const SceneOptions& options = {});

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_SCENE_H_
