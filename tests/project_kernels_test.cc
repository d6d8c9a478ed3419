// The batched float projection kernels (core/render/project_kernels.h), at
// every instruction set the CPU has, against the double reference
// ProjectSplat / ProjectSplatBackward, one Gaussian at a time, on hard
// cases: needles, Gaussians larger than the image, ones at the near plane,
// off-screen or past the FOV clamp, culled ones, and batches cut short.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/render/raster_project.h"
#include "core/render/rasterizer.h"
#include "tests/max_abs_diff.h"
#include "tests/per_simd_level_test.h"
#include "tests/reference_rasterizer.h"

namespace es {
namespace {

using reference::TestScene;

// RandomScene's mix (needles of 150:1, large blobs, near-plane, off-screen
// and FOV-clamped ones, opaque ones) plus the extremes.
TestScene HardScene(unsigned seed) {
  // 301: the last batch is cut short.
  TestScene s = reference::RandomScene(seed, 301 - 12, 3, 0, 160, 120);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double f = s.camera.fx;
  const Eigen::Vector4d q(0.9, 0.3, -0.2, 0.4);
  const auto at = [&](double u, double v, double z) {
    return s.camera.Unproject(u, v, z);
  };
  // Needles of 2000:1, across and along the view.
  s.Add(at(80, 60, 4), Eigen::Vector3d(2e-3, 2e-3, 4.0), q, 1);
  s.Add(at(30, 90, 3), Eigen::Vector3d(1.0, 5e-4, 5e-4),
        Eigen::Vector4d(1, 0, 0, 0), 2);
  s.Add(at(100, 20, 5), Eigen::Vector3d(3e-4, 0.6, 3e-4),
        Eigen::Vector4d(0.7, 0.7, 0, 0), 0);
  // Far larger than the image (sigma ~2000 px), and one centered off it.
  s.Add(at(60, 50, 2), Eigen::Vector3d::Constant(2000 * 2 / f), q, -2);
  s.Add(at(-400, 50, 3), Eigen::Vector3d::Constant(600 * 3 / f), q, 0);
  // Just in front of the near plane (kept), just behind it and behind the
  // camera (culled).
  s.Add(at(70, 70, 0.0102), Eigen::Vector3d::Constant(2e-5), q, 3);
  s.Add(at(70, 70, 0.0098), Eigen::Vector3d::Constant(2e-5), q, 3);
  s.Add(at(70, 70, -1), Eigen::Vector3d::Constant(0.1), q, 3);
  // Well off-screen (culled), beyond the FOV clamp but reaching in (kept).
  s.Add(at(-2000, 60, 3), Eigen::Vector3d::Constant(0.01), q, 3);
  s.Add(at(-60, 60, 2), Eigen::Vector3d(0.4, 0.05, 0.05), q, 3);
  // Too transparent (culled) and a zero quaternion (degenerate, culled).
  s.Add(at(80, 60, 3), Eigen::Vector3d::Constant(0.05), q, -7);
  s.Add(at(80, 60, 3), Eigen::Vector3d::Constant(0.05),
        Eigen::Vector4d::Zero(), 3);
  const int k_count = NumShCoeffs(s.sh_degree);
  for (int n = s.count - 12; n < s.count; ++n)
    for (int j = 0; j < 3 * k_count; ++j)
      s.sh[3 * k_count * n + j] = (uni(rng) - 0.5) * (j < 3 ? 2 : 0.6);
  return s;
}

// HardScene(seed) and the views of it the projection kernels take (they
// point into one another: not to be copied).
struct ProjectionCase {
  explicit ProjectionCase(unsigned seed)
      : scene(HardScene(seed)),
        view(scene.View()),
        cam(scene.camera),
        in(MakeProjectionInput(cam, view)) {}
  ProjectionCase(const ProjectionCase&) = delete;

  const TestScene scene;
  const SplatView view;
  const ProjectionCamera cam;
  const ProjectionInput in;
};

class ProjectKernelsTest : public PerSimdLevelTest {};

TEST_P(ProjectKernelsTest, ForwardMatchesDoubleReference) {
  const ProjectKernelSet& kernels = ProjectKernels(GetParam());
  for (unsigned seed = 0; seed < 3; ++seed) {
    const ProjectionCase c(seed);
    const auto& [scene, view, cam, in] = c;
    const int n = view.count;
    std::vector<ProjectedSplat> mine(n);
    std::vector<char> keep(n);
    for (int b = 0; b < n; b += kProjectBatch)
      kernels.forward(in, b, std::min(kProjectBatch, n - b), &mine[b],
                      &keep[b]);
    int kept = 0;
    for (int i = 0; i < n; ++i) {
      ProjectedSplat ref;
      const bool ref_keep = ProjectSplat(cam, view, i, &ref);
      ASSERT_EQ(keep[i] != 0, ref_keep) << "Gaussian " << i;
      if (!ref_keep) continue;
      ++kept;
      const ProjectedSplat& p = mine[i];
      for (int k = 0; k < 2; ++k)
        EXPECT_NEAR(p.mean2d[k], ref.mean2d[k],
                    1e-5 * (1 + std::abs(ref.mean2d[k])))
            << "Gaussian " << i;
      const double conic_scale =
          std::max({std::abs(ref.conic[0]), std::abs(ref.conic[1]),
                    std::abs(ref.conic[2])});
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(p.conic[k], ref.conic[k], 1e-4 * conic_scale)
            << "Gaussian " << i << " conic " << k;
      EXPECT_NEAR(p.depth, ref.depth, 1e-6 * ref.depth);
      EXPECT_NEAR(p.opacity, ref.opacity, 1e-6);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p.color[c], ref.color[c], 1e-5) << "Gaussian " << i;
      // Integer bounds from rounded floats: at most one apart.
      EXPECT_LE(std::abs(p.radius - ref.radius), 1) << "Gaussian " << i;
      const int mine_box[8] = {p.px0,     p.px1,     p.py0,     p.py1,
                               p.tile_x0, p.tile_x1, p.tile_y0, p.tile_y1};
      const int ref_box[8] = {ref.px0,     ref.px1,     ref.py0,
                              ref.py1,     ref.tile_x0, ref.tile_x1,
                              ref.tile_y0, ref.tile_y1};
      for (int k = 0; k < 8; ++k)
        EXPECT_LE(std::abs(mine_box[k] - ref_box[k]), 1)
            << "Gaussian " << i << " bound " << k;
    }
    // Most survive, and the extremes were culled where they should be.
    EXPECT_GT(kept, n / 2);
    EXPECT_LT(kept, n);
  }
}

// The largest |b| over one Gaussian's entries of a parameter.
double GroupScale(const std::vector<double>& b, size_t begin, size_t size) {
  double scale = 0;
  for (size_t j = begin; j < begin + size; ++j)
    scale = std::max(scale, std::abs(b[j]));
  return scale;
}

// max |a - b| over those entries, relative to `scale` (default: the largest
// reference entry there).
double GroupError(const std::vector<double>& a, const std::vector<double>& b,
                  size_t begin, size_t size, double scale = -1) {
  double diff = 0;
  for (size_t j = begin; j < begin + size; ++j)
    diff = std::max(diff, std::abs(a[j] - b[j]));
  if (scale < 0) scale = GroupScale(b, begin, size);
  return scale > 0 ? diff / scale : diff;
}

TEST_P(ProjectKernelsTest, BackwardMatchesDoubleReference) {
  const ProjectKernelSet& kernels = ProjectKernels(GetParam());
  for (unsigned seed = 0; seed < 3; ++seed) {
    const ProjectionCase c(seed);
    const auto& [scene, view, cam, in] = c;
    const int n = view.count, k_count = NumShCoeffs(view.sh_degree);
    constexpr int kStride = kTileGradHead + 4;
    std::vector<double> grad2d(static_cast<size_t>(kStride) * n);
    std::mt19937 rng(seed + 100);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (double& g : grad2d) g = uni(rng);
    std::vector<char> keep(n);
    SplatGradients ref, mine;
    ref.Resize(n, view.sh_degree, 0);
    mine.Resize(n, view.sh_degree, 0);
    for (int i = 0; i < n; ++i) {
      ProjectedSplat p;
      keep[i] = ProjectSplat(cam, view, i, &p);
      if (!keep[i]) continue;
      const double* g = &grad2d[static_cast<size_t>(kStride) * i];
      ProjectedGradient pg;
      pg.mean2d[0] = g[0];
      pg.mean2d[1] = g[1];
      for (int k = 0; k < 3; ++k) pg.conic[k] = g[2 + k];
      pg.opacity = g[5];
      for (int c = 0; c < 3; ++c) pg.color[c] = g[kTileGradHead + c];
      pg.depth = g[kTileGradHead + 3];
      ProjectSplatBackward(cam, view, i, pg, &ref);
    }
    const ProjectionGradients out = MakeProjectionGradients(&mine);
    for (int b = 0; b < n; b += kProjectBatch)
      kernels.backward(in, b, std::min(kProjectBatch, n - b), &keep[b],
                       &grad2d[static_cast<size_t>(kStride) * b], kStride,
                       out);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
      const size_t u = i;
      if (!keep[i]) {
        // Not written: still the zeros Resize put there.
        EXPECT_EQ(mine.means[3 * u], 0.0);
        EXPECT_EQ(mine.sh[3 * k_count * u], 0.0);
        continue;
      }
      // The rotation's and the scales' gradients both come from d cov3:
      // for a round Gaussian the rotation's is a difference of terms that
      // cancel (exactly 0 in theory), so its error is measured against
      // the two together.
      const double shape_scale =
          std::max(GroupScale(ref.quats, 4 * u, 4),
                   GroupScale(ref.log_scales, 3 * u, 3));
      const double errors[5] = {
          GroupError(mine.means, ref.means, 3 * u, 3),
          GroupError(mine.log_scales, ref.log_scales, 3 * u, 3),
          GroupError(mine.quats, ref.quats, 4 * u, 4, shape_scale),
          GroupError(mine.opacity_logits, ref.opacity_logits, u, 1),
          GroupError(mine.sh, ref.sh, 3 * k_count * u, 3 * k_count)};
      for (int k = 0; k < 5; ++k) {
        EXPECT_LT(errors[k], 2e-4) << "Gaussian " << i << " group " << k;
        worst = std::max(worst, errors[k]);
      }
    }
    RecordProperty("worst_relative_error_seed_" + std::to_string(seed),
                   std::to_string(worst));
  }
}

// The rasterizer's float path (these kernels) against its double path
// (the reference projection) on the hard scene: images and gradients.
TEST_P(ProjectKernelsTest, FloatRenderMatchesDoubleRender) {
  const TestScene scene = HardScene(4);
  struct Pass {
    RenderResult image;
    SplatGradients grads;
  };
  const auto run = [&](bool use_double) {
    RenderOptions o;
    o.simd = GetParam();
    o.use_double = use_double;
    Rasterizer r;
    Pass p;
    r.Forward(scene.camera, scene.View(), o, &p.image);
    std::vector<double> d_rgb(p.image.rgb.size()),
        d_alpha(p.image.alpha.size());
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (double& x : d_rgb) x = uni(rng);
    for (double& x : d_alpha) x = uni(rng);
    r.Backward({d_rgb.data(), d_alpha.data(), nullptr, nullptr}, &p.grads);
    return p;
  };
  const Pass f = run(false), d = run(true);
  const auto rel = [](const std::vector<double>& a,
                      const std::vector<double>& b) {
    const AbsDiff d = MaxAbsDiff(a, b);
    return d.diff / (1 + d.scale);
  };
  double peak = 0;
  for (double a : d.image.alpha) peak = std::max(peak, a);
  EXPECT_GT(peak, 0.5);
  EXPECT_LT(rel(f.image.rgb, d.image.rgb), 1e-4);
  EXPECT_LT(rel(f.image.alpha, d.image.alpha), 1e-4);
  EXPECT_LT(rel(f.grads.means, d.grads.means), 1e-3);
  EXPECT_LT(rel(f.grads.log_scales, d.grads.log_scales), 1e-3);
  EXPECT_LT(rel(f.grads.quats, d.grads.quats), 1e-3);
  EXPECT_LT(rel(f.grads.opacity_logits, d.grads.opacity_logits), 1e-3);
  EXPECT_LT(rel(f.grads.sh, d.grads.sh), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Levels, ProjectKernelsTest, AllSimdLevels(),
                         SimdLevelTestName);

}  // namespace
}  // namespace es
