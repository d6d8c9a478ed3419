#ifndef EULERSPLAT_CORE_VIZ_TRACKS_H_
#define EULERSPLAT_CORE_VIZ_TRACKS_H_

#include <cstdint>
#include <deque>
#include <vector>

#include <opencv2/core.hpp>

#include "core/model/camera.h"

namespace es {

// `count` distinct indices in [0, n), drawn from std::mt19937(seed),
// ascending; all of them when count >= n.
std::vector<int> SelectTrackSubset(int n, int count, uint32_t seed);

// The last `length` 3D positions of a few Gaussians, drawn over a frame as
// projected polylines colored by age (dark purple oldest, yellow newest), as
// in the paper's flow visualization.
class TrackHistory {
 public:
  TrackHistory(int num_tracks, int length);

  // positions: num_tracks x 3. restarted (empty or num_tracks entries):
  // track k jumped since the last Push (its Gaussian wrapped back to the
  // canonical position), so no segment joins its two positions.
  void Push(const double* positions, const std::vector<bool>& restarted);

  // Draws every segment whose ends are both in front of the camera onto
  // bgr (CV_8UC3, the camera's size). The polylines are not occluded by
  // the scene: they show where the water goes, as seen from the camera.
  void Draw(const Camera& camera, cv::Mat* bgr) const;

  int steps() const { return static_cast<int>(history_.size()); }

 private:
  struct Step {
    std::vector<double> positions;  // num_tracks x 3
    std::vector<bool> restarted;
  };
  int num_tracks_;
  int length_;
  std::deque<Step> history_;  // oldest first
  cv::Mat colors_;            // 1 x 256 CV_8UC3 colormap
};

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_TRACKS_H_
