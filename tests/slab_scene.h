#ifndef EULERSPLAT_TESTS_SLAB_SCENE_H_
#define EULERSPLAT_TESTS_SLAB_SCENE_H_

// Pieces of the trainers' test scenes: a slab of random Gaussians around
// the origin, and the frames rendered from it, with their water masks.

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/io/scene.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"

namespace es {

// Draws Gaussian i of *truth (SH degree 0): a mean in a 2.4 x 1.8 x 0.4
// slab, log-scales about log(scale), a random rotation, opacity 0.8 and a
// colour in [0.1, 0.9], which it returns.
inline Eigen::Vector3d DrawSlabGaussian(double scale, int i, std::mt19937* rng,
                                        GaussianSet* truth) {
  std::uniform_real_distribution<double> u(-1, 1);
  truth->means[3 * i] = 1.2 * u(*rng);
  truth->means[3 * i + 1] = 0.9 * u(*rng);
  truth->means[3 * i + 2] = 0.2 * u(*rng);
  for (int a = 0; a < 3; ++a)
    truth->log_scales[3 * i + a] = std::log(scale) + 0.3 * u(*rng);
  for (int a = 0; a < 4; ++a)
    truth->quats[4 * i + a] = (a == 0) + 0.5 * u(*rng);
  truth->opacity_logits[i] = Logit(0.8);
  Eigen::Vector3d color;
  for (int c = 0; c < 3; ++c) {
    color[c] = 0.5 + 0.4 * u(*rng);
    truth->sh[3 * i + c] = (color[c] - 0.5) / kShC0;
  }
  return color;
}

// The view of `truth` whose one extra channel, kept in *water, marks the
// Gaussians with x > 0 as water (1): what the frames' masks render.
inline SplatView WaterMarkedView(const GaussianSet& truth,
                                 std::vector<double>* water) {
  water->assign(truth.size(), 0.0);
  for (int i = 0; i < truth.size(); ++i) (*water)[i] = truth.means[3 * i] > 0;
  SplatView view = SplatView::Of(truth);
  view.num_extra = 1;
  view.extra = water->data();
  return view;
}

// The frame `view` renders at `camera` (one extra channel: the water
// probability), its image and its mask in float.
inline Frame RenderedFrame(const Camera& camera, const SplatView& view,
                           Rasterizer* rasterizer, RenderResult* render) {
  Frame f;
  f.camera = camera;
  rasterizer->Forward(camera, view, RenderOptions(), render);
  cv::Mat(camera.height, camera.width, CV_64FC3, render->rgb.data())
      .convertTo(f.image, CV_32F);
  cv::Mat(camera.height, camera.width, CV_64FC1, render->extra.data())
      .convertTo(f.mask, CV_32F);
  return f;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_SLAB_SCENE_H_
