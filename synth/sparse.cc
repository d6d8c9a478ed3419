#include "synth/sparse.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glog/logging.h>

#include "synth/random.h"

namespace es {
namespace {

// A point is seen when its depth is within this fraction of the rendered
// depth (discs near a point shift the expected depth a little).
constexpr double kDepthTolerance = 0.03;
// Points seen in fewer frames are not triangulable.
constexpr int kMinTrackLength = 2;

}  // namespace

ColmapModel MakeSynthSparse(const std::vector<Camera>& cameras,
                            const GaussianSet& scenery,
                            const std::vector<cv::Mat>& depths,
                            const SynthSparseOptions& options) {
  CHECK_EQ(cameras.size(), depths.size());
  CHECK(!cameras.empty());
  ColmapModel model;
  const Camera& first = cameras.front();
  ColmapCamera camera;
  camera.id = 1;
  camera.model = "PINHOLE";
  camera.width = first.width;
  camera.height = first.height;
  camera.params = {first.fx, first.fy, first.cx, first.cy};
  model.cameras[camera.id] = camera;
  for (const Camera& c : cameras) {
    ColmapImage image;
    image.id = c.image_id;
    image.q_cw = c.q_cw;
    image.t_cw = c.t_cw;
    image.camera_id = camera.id;
    image.name = c.image_name;
    model.images[image.id] = image;
  }

  // Visit the scenery in a random order until enough points are tracked.
  SynthRandom random(options.seed);
  std::vector<int> order(scenery.size());
  std::iota(order.begin(), order.end(), 0);
  for (int i = static_cast<int>(order.size()) - 1; i > 0; --i)
    std::swap(order[i], order[random.Next() % (i + 1)]);

  for (int index : order) {
    if (static_cast<int>(model.points.size()) >= options.num_points) break;
    const Eigen::Vector3d x(scenery.means[3 * index],
                            scenery.means[3 * index + 1],
                            scenery.means[3 * index + 2]);
    std::vector<std::pair<int, Eigen::Vector2d>> seen;
    for (size_t f = 0; f < cameras.size(); ++f) {
      const Eigen::Vector3d xc = cameras[f].WorldToCamera(x);
      if (xc.z() <= 0) continue;
      const Eigen::Vector2d uv = cameras[f].Project(xc);
      const int j = static_cast<int>(std::floor(uv.x()));
      const int i = static_cast<int>(std::floor(uv.y()));
      if (i < 0 || j < 0 || i >= depths[f].rows || j >= depths[f].cols)
        continue;
      const double depth = depths[f].at<float>(i, j);
      if (std::abs(depth - xc.z()) > kDepthTolerance * xc.z()) continue;
      seen.emplace_back(static_cast<int>(f), uv);
    }
    if (static_cast<int>(seen.size()) < kMinTrackLength) continue;

    ColmapPoint3D point;
    point.id = static_cast<int64_t>(model.points.size()) + 1;
    point.xyz = x + options.point_noise * Eigen::Vector3d(random.Normal(),
                                                          random.Normal(),
                                                          random.Normal());
    const int k = scenery.sh_coeffs();
    for (int c = 0; c < 3; ++c) {
      const double v = kShC0 * scenery.sh[3 * k * index + c] + 0.5;
      point.rgb[c] = static_cast<uint8_t>(
          std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
    point.error = options.pixel_noise * std::abs(random.Normal()) + 0.1;
    for (const auto& [f, uv] : seen) {
      ColmapImage& image = model.images.at(cameras[f].image_id);
      const Eigen::Vector2d noisy =
          uv + options.pixel_noise *
                   Eigen::Vector2d(random.Normal(), random.Normal());
      point.track.emplace_back(image.id,
                               static_cast<int>(image.points2d.size()));
      image.points2d.push_back(noisy);
      image.point3d_ids.push_back(point.id);
    }
    model.points.push_back(std::move(point));
  }
  return model;
}

}  // namespace es
