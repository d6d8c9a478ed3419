#ifndef EULERSPLAT_CORE_IO_UNDISTORT_H_
#define EULERSPLAT_CORE_IO_UNDISTORT_H_

#include <string>

#include <opencv2/core.hpp>

#include "core/io/colmap_io.h"
#include "core/model/camera.h"

namespace es {

// Turns a COLMAP camera into the pinhole camera the renderer uses.
// SIMPLE_PINHOLE and PINHOLE are used as they are; SIMPLE_RADIAL, RADIAL and
// OPENCV frames are resampled onto a pinhole camera of the same size, focal
// length and principal point (pixels that fall outside the source repeat its
// border). Other models are rejected.
class Undistorter {
 public:
  // Throws InputError naming `source` (the model's file) and the camera when
  // the model is not supported or its size or focal length is invalid.
  Undistorter(const ColmapCamera& camera, const std::string& source);

  // Width, height and intrinsics of the undistorted frames; pose unset.
  const Camera& pinhole() const { return pinhole_; }
  // True if frames need no resampling (pinhole model or zero distortion).
  bool is_identity() const;
  // Resamples a frame (any channel count, same size as the camera). The
  // first call builds the resampling maps (not thread-safe).
  cv::Mat Apply(const cv::Mat& image) const;

 private:
  Camera pinhole_;
  double dist_[4] = {0, 0, 0, 0};  // OpenCV order: k1 k2 p1 p2
  // Source pixel (OpenCV coordinates) per output, built on first use.
  mutable cv::Mat map_x_, map_y_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_UNDISTORT_H_
