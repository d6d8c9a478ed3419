#ifndef EULERSPLAT_APPS_COMMON_RASTER_BENCH_SCENE_H_
#define EULERSPLAT_APPS_COMMON_RASTER_BENCH_SCENE_H_

// The random scene and image gradients the rasterizer benchmarks render
// (apps/bench_rasterizer.cc on the CPU, apps/cuda/bench_cuda_rasterizer.cc
// on the device), so both time the same work. Header-only.

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/render/rasterizer.h"

namespace es {

struct BenchScene {
  Camera camera;
  GaussianSet gaussians;
  std::vector<double> extra;  // one channel, like the dynamic probability
  SplatView View() const {
    SplatView v = SplatView::Of(gaussians);
    v.num_extra = 1;
    v.extra = extra.data();
    return v;
  }
};

// Gaussians spread over the view at depths 2..20, footprints with sigma of
// 1..12 px (3-sigma radii from a few to tens of pixels), random anisotropy
// and rotation, SH degree 3 as 3DGS trains.
inline BenchScene MakeScene(int width, int height, int count) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  BenchScene s;
  Camera& c = s.camera;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.9 * width;
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  GaussianSet& g = s.gaussians;
  g.SetShDegree(3);
  g.Resize(count);
  const int k = g.sh_coeffs();
  for (int n = 0; n < count; ++n) {
    const double z = 2 + 18 * uni(rng);
    const double u = width * (1.2 * uni(rng) - 0.1);
    const double v = height * (1.2 * uni(rng) - 0.1);
    const Eigen::Vector3d p = c.Unproject(u, v, z);
    const double sigma_px = std::exp(std::log(1.0) + std::log(12.0) * uni(rng));
    for (int i = 0; i < 3; ++i) {
      g.means[3 * n + i] = p[i];
      g.log_scales[3 * n + i] =
          std::log(sigma_px * z / c.fx * (0.5 + uni(rng)));
    }
    for (int i = 0; i < 4; ++i) g.quats[4 * n + i] = normal(rng);
    g.opacity_logits[n] = -1 + 4 * uni(rng);
    for (int j = 0; j < 3 * k; ++j) {
      g.sh[3 * k * n + j] = (j < 3 ? 1.0 : 0.2) * normal(rng);
    }
    s.extra.push_back(uni(rng));
  }
  return s;
}

// Small random image gradients, as a loss would give.
struct BenchImageGrads {
  std::vector<double> rgb, alpha, depth, extra;
  explicit BenchImageGrads(int pixels)
      : rgb(3 * pixels), alpha(pixels), depth(pixels), extra(pixels) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(-1e-3, 1e-3);
    for (auto* v : {&rgb, &alpha, &depth, &extra}) {
      for (double& x : *v) x = uni(rng);
    }
  }
};

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_RASTER_BENCH_SCENE_H_
