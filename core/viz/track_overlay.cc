#include "core/viz/track_overlay.h"

#include <algorithm>
#include <cstdio>

namespace es {

TrackOverlay::TrackOverlay(const LoopModel& model, const std::string& out_dir,
                           double fps, int count, int length, uint32_t seed)
    : out_dir_(out_dir),
      video_(out_dir + "/tracks", fps),
      tracked_(SelectTrackSubset(model.num_dynamic(), count, seed)),
      history_(static_cast<int>(tracked_.size()), length),
      positions_(3 * tracked_.size()) {}

void TrackOverlay::Add(const LoopRenderer& renderer, const Camera& camera,
                       const cv::Mat& bgr) {
  const std::vector<double>& x = renderer.positions();
  const std::vector<int>& cycle = renderer.cycle_indices();
  std::vector<bool> restarted(tracked_.size(), false);
  for (size_t i = 0; i < tracked_.size(); ++i) {
    std::copy_n(&x[3 * tracked_[i]], 3, &positions_[3 * i]);
    // A cycle index that did not move forward by one is a reset.
    restarted[i] = !previous_cycle_.empty() &&
                   cycle[tracked_[i]] != previous_cycle_[tracked_[i]] + 1;
  }
  previous_cycle_ = cycle;
  history_.Push(positions_.data(), restarted);
  cv::Mat overlay = bgr.clone();
  history_.Draw(camera, &overlay);
  video_.Add(overlay);
}

void TrackOverlay::Finish(int num_dynamic) {
  video_.Finish(out_dir_ + "/tracks.mp4");
  std::printf("tracks of %zu of %d water Gaussians -> %s/tracks.mp4\n",
              tracked_.size(), num_dynamic, out_dir_.c_str());
}

}  // namespace es
