#ifndef EULERSPLAT_CORE_VIZ_TRACK_OVERLAY_H_
#define EULERSPLAT_CORE_VIZ_TRACK_OVERLAY_H_

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/loop/loop_model.h"
#include "core/loop/loop_renderer.h"
#include "core/model/camera.h"
#include "core/viz/tracks.h"
#include "core/viz/video_writer.h"

namespace es {

// es_animate --tracks: the recent positions of a seeded subset of the
// water Gaussians drawn over each frame, into their own video
// (out_dir/tracks/ and, on Finish, out_dir/tracks.mp4).
class TrackOverlay {
 public:
  // `count` water Gaussians of the model drawn from std::mt19937(seed),
  // each with its last `length` positions.
  TrackOverlay(const LoopModel& model, const std::string& out_dir, double fps,
               int count, int length, uint32_t seed);

  // The renderer's current positions seen from `camera`, drawn over `bgr`
  // (the frame it rendered there) as the next frame of the video.
  void Add(const LoopRenderer& renderer, const Camera& camera,
           const cv::Mat& bgr);

  // Encodes the video and says so.
  void Finish(int num_dynamic);

 private:
  std::string out_dir_;
  VideoWriter video_;
  std::vector<int> tracked_;
  TrackHistory history_;
  std::vector<double> positions_;
  std::vector<int> previous_cycle_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_VIZ_TRACK_OVERLAY_H_
