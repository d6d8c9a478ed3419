#include "core/viz/tracks.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/render/rasterizer.h"

namespace es {

std::vector<int> SelectTrackSubset(int n, int count, uint32_t seed) {
  CHECK_GE(n, 0);
  CHECK_GE(count, 0);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  if (count >= n) return all;
  std::mt19937 rng(seed);
  // Partial Fisher-Yates: the first `count` entries are a uniform subset.
  for (int i = 0; i < count; ++i) {
    std::uniform_int_distribution<int> pick(i, n - 1);
    std::swap(all[i], all[pick(rng)]);
  }
  all.resize(count);
  std::sort(all.begin(), all.end());
  return all;
}

TrackHistory::TrackHistory(int num_tracks, int length)
    : num_tracks_(num_tracks), length_(length) {
  CHECK_GE(num_tracks, 0);
  CHECK_GE(length, 2);
  cv::Mat ramp(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = i;
  cv::applyColorMap(ramp, colors_, cv::COLORMAP_PLASMA);
}

void TrackHistory::Push(const double* positions,
                        const std::vector<bool>& restarted) {
  CHECK(restarted.empty() ||
        static_cast<int>(restarted.size()) == num_tracks_);
  Step step;
  step.positions.assign(positions, positions + 3 * num_tracks_);
  step.restarted = restarted.empty() ? std::vector<bool>(num_tracks_, false)
                                     : restarted;
  history_.push_back(std::move(step));
  if (static_cast<int>(history_.size()) > length_) history_.pop_front();
}

void TrackHistory::Draw(const Camera& camera, cv::Mat* bgr) const {
  CHECK_EQ(bgr->type(), CV_8UC3);
  CHECK(bgr->cols == camera.width && bgr->rows == camera.height);
  const int steps = static_cast<int>(history_.size());
  // Fixed-point drawing keeps sub-pixel motion visible.
  constexpr int kShift = 4;
  const double scale = 1 << kShift;
  const int thickness = std::max(1, camera.width / 320);
  for (int s = 1; s < steps; ++s) {
    const Step& a = history_[s - 1];
    const Step& b = history_[s];
    // Age 0 is the newest segment; the colormap runs dark to bright.
    const int age = steps - 1 - s;
    const int level = 255 - 255 * age / (length_ - 1);
    const cv::Vec3b c = colors_.at<cv::Vec3b>(0, std::clamp(level, 0, 255));
    const cv::Scalar color(c[0], c[1], c[2]);
    for (int k = 0; k < num_tracks_; ++k) {
      if (b.restarted[k]) continue;
      const Eigen::Vector3d pa = camera.WorldToCamera(
          Eigen::Vector3d(a.positions.data() + 3 * k));
      const Eigen::Vector3d pb = camera.WorldToCamera(
          Eigen::Vector3d(b.positions.data() + 3 * k));
      if (pa.z() <= kNearPlane || pb.z() <= kNearPlane) continue;
      // COLMAP pixel coordinates put pixel (j, i)'s center at j + 0.5;
      // OpenCV's drawing at j.
      const Eigen::Vector2d ua = camera.Project(pa).array() - 0.5;
      const Eigen::Vector2d ub = camera.Project(pb).array() - 0.5;
      if (!ua.allFinite() || !ub.allFinite()) continue;
      const double limit = 4.0 * (camera.width + camera.height);
      if (ua.cwiseAbs().maxCoeff() > limit ||
          ub.cwiseAbs().maxCoeff() > limit) {
        continue;  // far off-screen: outside the fixed-point range
      }
      cv::line(*bgr, cv::Point(std::lround(ua.x() * scale),
                               std::lround(ua.y() * scale)),
               cv::Point(std::lround(ub.x() * scale),
                         std::lround(ub.y() * scale)),
               color, thickness, cv::LINE_AA, kShift);
    }
  }
}

}  // namespace es
