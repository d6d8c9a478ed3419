// The CUDA rasterizer against its CPU twin (the float path of
// core/render/rasterizer.h, itself matched to a per-pixel reference): each
// kernel on its own (projection and its backward, binning), then whole
// frames, forward images and every gradient, on random scenes and on the
// hard cases of the CPU tests (needles across tile corners, huge and
// near-plane Gaussians, off-screen ones, opaque stacks, image borders).
// Skips when no CUDA device is present.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "apps/common/raster_bench_scene.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "core/render/cuda/device_splats.h"
#include "core/render/cuda/raster_kernels.h"
#include "core/render/project_kernels.h"
#include "core/render/raster_project.h"
#include "core/render/rasterizer.h"
#include "tests/cuda/require_gpu.h"
#include "tests/raster_test_scene.h"

namespace es {
namespace cuda {
namespace {

using reference::NeedleScene;
using reference::RandomScene;
using reference::StackedScene;
using reference::TestScene;

// Where `got` and `want` differ by more than tol times the largest |want|
// (or tol itself when want is all zeros): how many entries, and the
// largest difference so scaled. Float rounding, and a decision flipped
// exactly at a cut-off (alpha = 1/255, T = 1e-4) in a rare pixel, are all
// two float rasterizers may differ by.
struct Mismatch {
  size_t count = 0;
  double largest = 0;
};
Mismatch Compare(const std::vector<double>& got,
                 const std::vector<double>& want, double tol) {
  EXPECT_EQ(got.size(), want.size());
  double scale = 0;
  for (double v : want) scale = std::max(scale, std::abs(v));
  if (scale == 0) scale = 1;
  Mismatch m;
  for (size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
    const double d = std::abs(got[i] - want[i]) / scale;
    if (!(d <= tol)) ++m.count;  // NaN counts
    if (!(d <= m.largest)) m.largest = d;
  }
  return m;
}

// At most max_fraction of the entries off by more than tol (relative to
// the largest), none off by more than cap.
void ExpectClose(const std::vector<double>& got,
                 const std::vector<double>& want, double tol,
                 double max_fraction, double cap, const std::string& name) {
  const Mismatch m = Compare(got, want, tol);
  EXPECT_LE(m.count, max_fraction * want.size())
      << name << ": " << m.count << " of " << want.size()
      << " entries off by more than " << tol << " (largest " << m.largest
      << ")";
  EXPECT_LE(m.largest, cap) << name;
}

void ExpectImagesClose(const RenderResult& got, const RenderResult& want) {
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  ExpectClose(got.rgb, want.rgb, 2e-5, 0.005, 0.05, "rgb");
  ExpectClose(got.alpha, want.alpha, 2e-5, 0.005, 0.05, "alpha");
  ExpectClose(got.depth, want.depth, 2e-5, 0.005, 0.05, "depth");
  ExpectClose(got.extra, want.extra, 2e-5, 0.005, 0.05, "extra");
}

void ExpectGradientsClose(const SplatGradients& got,
                          const SplatGradients& want, double tol,
                          double max_fraction) {
  using Array = std::vector<double> SplatGradients::*;
  const std::pair<const char*, Array> kArrays[] = {
      {"means", &SplatGradients::means},
      {"log_scales", &SplatGradients::log_scales},
      {"quats", &SplatGradients::quats},
      {"opacity_logits", &SplatGradients::opacity_logits},
      {"sh", &SplatGradients::sh},
      {"extra", &SplatGradients::extra}};
  for (const auto& [name, array] : kArrays) {
    ExpectClose(got.*array, want.*array, tol, max_fraction, 0.05, name);
  }
}

// Random image gradients of a loss.
struct ImageWeights {
  std::vector<double> rgb, alpha, depth, extra;
  ImageWeights(int pixels, int num_extra, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1, 1);
    for (int i = 0; i < 3 * pixels; ++i) rgb.push_back(uni(rng));
    for (int i = 0; i < pixels; ++i) alpha.push_back(uni(rng));
    for (int i = 0; i < pixels; ++i) depth.push_back(0.2 * uni(rng));
    for (int i = 0; i < pixels * num_extra; ++i) extra.push_back(uni(rng));
  }
  RenderGradients View() const {
    return {rgb.data(), alpha.data(), depth.data(),
            extra.empty() ? nullptr : extra.data()};
  }
};

// One frame through a rasterizer, forward and backward.
struct FrameOutput {
  RenderResult images;
  SplatGradients grads;
  int visible = 0;
  std::vector<int> radii;
  std::vector<double> mean2d;
};

// R: Rasterizer or DeviceRasterizer (the same interface).
template <typename R>
FrameOutput RenderWith(const Camera& camera, const SplatView& view,
                       const ImageWeights& w) {
  R r;
  FrameOutput out;
  r.Forward(camera, view, reference::TestRenderOptions(), &out.images);
  r.Backward(w.View(), &out.grads);
  out.visible = r.num_visible();
  r.Radii(&out.radii);
  r.Mean2dGradients(&out.mean2d);
  return out;
}

struct Frames {
  FrameOutput cpu, gpu;
};

Frames RenderBoth(const Camera& camera, const SplatView& view,
                  unsigned seed) {
  const ImageWeights w(camera.width * camera.height, view.num_extra, seed);
  return {RenderWith<Rasterizer>(camera, view, w),
          RenderWith<DeviceRasterizer>(camera, view, w)};
}

// Radii and culling may differ where a float bound lands on a whole
// number (the library exp and log against the CPU's polynomials): at most
// `fraction` of the Gaussians, as for the gradient entries.
void ExpectFramesMatch(const Frames& f, double fraction = 0.002) {
  const size_t count = f.cpu.radii.size();
  EXPECT_LE(std::abs(f.gpu.visible - f.cpu.visible), fraction * count);
  ASSERT_EQ(f.gpu.radii.size(), count);
  size_t radii_off = 0;
  for (size_t n = 0; n < count; ++n)
    radii_off += f.gpu.radii[n] != f.cpu.radii[n];
  EXPECT_LE(radii_off, fraction * count);
  ExpectImagesClose(f.gpu.images, f.cpu.images);
  ExpectGradientsClose(f.gpu.grads, f.cpu.grads, 2e-3, fraction);
  ExpectClose(f.gpu.mean2d, f.cpu.mean2d, 2e-3, fraction, 0.05, "mean2d");
}

// ------------------------------------------------------------ the kernels

// A scene's splat arrays on the device, and the projection's view of them.
struct DeviceScene {
  DeviceSplats splats;
  ProjectionInput in;
  explicit DeviceScene(const TestScene& s) {
    splats.Upload(s.View());
    in = DeviceProjectionInput(s.camera, splats.View());
  }
  const double* extra() const { return splats.View().extra; }
};

// The CPU float projection of every Gaussian of s.
void CpuProject(const TestScene& s, std::vector<ProjectedSplat>* out,
                std::vector<char>* keep) {
  const ProjectionInput in =
      MakeProjectionInput(ProjectionCamera(s.camera), s.View());
  out->assign(s.count, ProjectedSplat());
  keep->assign(s.count, 0);
  const auto forward = ProjectKernels(SimdLevel::kAuto).forward;
  for (int b = 0; b < s.count; b += kProjectBatch) {
    forward(in, b, std::min(kProjectBatch, s.count - b), &(*out)[b],
            &(*keep)[b]);
  }
}

// Gaussians behind the camera, on and near the near plane, far off-screen,
// too transparent, degenerate, non-finite and huge, among ordinary ones.
TestScene CullingScene() {
  TestScene s = RandomScene(5, 12, 1, 1);
  const Eigen::Vector4d q(1, 0.2, -0.1, 0.3);
  const Eigen::Vector3d small(0.02, 0.03, 0.02);
  const double w = s.camera.width, h = s.camera.height;
  s.Add(s.camera.Unproject(20, 20, -1.0), small, q, 2);    // behind
  s.Add(s.camera.Unproject(20, 20, 0.005), small, q, 2);   // before near
  s.Add(s.camera.Unproject(20, 20, 0.011), small, q, 2);   // just past it
  s.Add(s.camera.Unproject(-6 * w, 10, 3), small, q, 2);   // far left
  s.Add(s.camera.Unproject(10, 5 * h, 3), small, q, 2);    // far below
  s.Add(s.camera.Unproject(20, 20, 3), small, q, -7);      // o < 1/255
  s.Add(s.camera.Unproject(20, 20, 3), small, Eigen::Vector4d::Zero(), 2);
  s.Add(s.camera.Unproject(20, 20, 3), Eigen::Vector3d(40, 30, 50), q, 1);
  s.Add(s.camera.Unproject(1, 1, 2), Eigen::Vector3d(1e-6, 1e-6, 0.5), q, 3);
  s.Add(s.camera.Unproject(20, 20, 3), small, q, 2);
  s.means[3 * (s.count - 1)] = std::numeric_limits<double>::quiet_NaN();
  return s;
}

std::vector<TestScene> KernelScenes() {
  std::vector<TestScene> scenes;
  for (int degree = 0; degree <= 3; ++degree) {
    scenes.push_back(RandomScene(100 + degree, 60, degree, degree % 3));
  }
  scenes.push_back(StackedScene(3, 2));
  scenes.push_back(NeedleScene());
  scenes.push_back(CullingScene());
  return scenes;
}

TEST(CudaProjectTest, ForwardMatchesCpuKernels) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  for (const TestScene& s : KernelScenes()) {
    std::vector<ProjectedSplat> want;
    std::vector<char> keep;
    CpuProject(s, &want, &keep);
    DeviceScene d(s);
    const int nf = 4 + s.num_extra;
    DeviceBuffer<ProjectedGaussian> projected(s.count);
    DeviceBuffer<float> features(static_cast<size_t>(nf) * s.count);
    DeviceBuffer<int> tiles(s.count), visible(1);
    ProjectForward(d.in, s.count, s.num_extra, d.extra(),
                   projected.data(), features.data(), tiles.data(),
                   visible.data());
    const std::vector<ProjectedGaussian> got = projected.Download();
    const std::vector<float> feat = features.Download();
    const std::vector<int> got_tiles = tiles.Download();
    int kept = 0, bounds_off = 0;
    for (int n = 0; n < s.count; ++n) {
      SCOPED_TRACE("Gaussian " + std::to_string(n));
      EXPECT_EQ(got_tiles[n] > 0, keep[n] != 0);
      if (!keep[n] || got_tiles[n] == 0) {
        EXPECT_EQ(got[n].radius, 0);
        continue;
      }
      ++kept;
      const ProjectedSplat& p = want[n];
      const ProjectedGaussian& g = got[n];
      const auto near = [](double a, double b) {
        return std::abs(a - b) <= 1e-5 * std::max(1.0, std::abs(b));
      };
      EXPECT_TRUE(near(g.mean[0], p.mean2d[0])) << g.mean[0];
      EXPECT_TRUE(near(g.mean[1], p.mean2d[1])) << g.mean[1];
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(g.conic[k], p.conic[k],
                    1e-4 * (std::abs(p.conic[0]) + std::abs(p.conic[2])));
      }
      EXPECT_TRUE(near(g.opacity, p.opacity));
      EXPECT_TRUE(near(g.depth, p.depth));
      for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(near(feat[nf * n + c], p.color[c])) << c;
      EXPECT_EQ(feat[nf * n + 3], g.depth);
      for (int e = 0; e < s.num_extra; ++e) {
        EXPECT_EQ(feat[nf * n + 4 + e],
                  static_cast<float>(s.extra[s.num_extra * n + e]));
      }
      // Whole-number bounds: one off where a float bound lands on a
      // whole number (library exp and log against the CPU's polynomials).
      const int got_ints[9] = {g.radius,  g.px0,     g.px1,
                               g.py0,     g.py1,     g.tile_x0,
                               g.tile_x1, g.tile_y0, g.tile_y1};
      const int want_ints[9] = {p.radius,  p.px0,     p.px1,
                                p.py0,     p.py1,     p.tile_x0,
                                p.tile_x1, p.tile_y0, p.tile_y1};
      bool same = true;
      for (int k = 0; k < 9; ++k) {
        EXPECT_LE(std::abs(got_ints[k] - want_ints[k]), 1) << "bound " << k;
        same = same && got_ints[k] == want_ints[k];
      }
      bounds_off += !same;
      EXPECT_EQ(got_tiles[n],
                (g.tile_x1 - g.tile_x0) * (g.tile_y1 - g.tile_y0));
    }
    EXPECT_LE(bounds_off, kept / 50);
    int got_visible = 0;
    CopyToHost(&got_visible, visible.data(), sizeof(int));
    EXPECT_EQ(got_visible, kept);
    EXPECT_GT(kept, 0);
  }
}

// The CPU half runs without a device too.
TEST(CudaProjectTest, CullingSceneCullsWhatTheCpuCulls) {
  const TestScene s = CullingScene();
  std::vector<ProjectedSplat> want;
  std::vector<char> keep;
  CpuProject(s, &want, &keep);
  // Behind, before the near plane, far off-screen, transparent,
  // degenerate, non-finite: culled; just past the near plane, huge and a
  // needle in a corner: kept (the scene's last 10 Gaussians).
  const int first = s.count - 10;
  const std::vector<bool> expected = {false, false, true,  false,
                                      false, false, false, true,
                                      true,  false};
  for (int i = 0; i < 10; ++i)
    EXPECT_EQ(keep[first + i] != 0, expected[i]) << "CPU, case " << i;
  ES_REQUIRE_GPU("CUDA rasterizer");
  ExpectFramesMatch(RenderBoth(s.camera, s.View(), 3));
}

TEST(CudaProjectTest, BackwardMatchesCpuKernels) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  for (const TestScene& s : KernelScenes()) {
    std::vector<ProjectedSplat> projected;
    std::vector<char> keep;
    CpuProject(s, &projected, &keep);
    // Random 2D gradients, one row per Gaussian.
    const int stride = kTileGradHead + 4 + s.num_extra;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(-1, 1);
    std::vector<double> grad2d(static_cast<size_t>(stride) * s.count);
    for (double& g : grad2d) g = uni(rng);
    SplatGradients want, got;
    want.Resize(s.count, s.sh_degree, s.num_extra);
    got.Resize(s.count, s.sh_degree, s.num_extra);
    const ProjectionInput in =
        MakeProjectionInput(ProjectionCamera(s.camera), s.View());
    const ProjectionGradients out = MakeProjectionGradients(&want);
    const auto backward = ProjectKernels(SimdLevel::kAuto).backward;
    for (int b = 0; b < s.count; b += kProjectBatch) {
      backward(in, b, std::min(kProjectBatch, s.count - b), &keep[b],
               &grad2d[static_cast<size_t>(stride) * b], stride, out);
    }
    for (int n = 0; n < s.count; ++n) {
      for (int e = 0; e < s.num_extra; ++e) {
        want.extra[s.num_extra * n + e] =
            keep[n] ? grad2d[stride * n + kTileGradHead + 4 + e] : 0.0;
      }
    }

    DeviceScene d(s);
    DeviceBuffer<ProjectedGaussian> dev_projected(s.count);
    DeviceBuffer<float> features(static_cast<size_t>(4 + s.num_extra) *
                                 s.count);
    DeviceBuffer<int> tiles(s.count), visible(1);
    ProjectForward(d.in, s.count, s.num_extra, d.extra(),
                   dev_projected.data(), features.data(), tiles.data(),
                   visible.data());
    DeviceBuffer<double> dev_grad2d;
    dev_grad2d.Upload(grad2d);
    DeviceGradientArrays arrays;
    arrays.Resize(s.count, s.sh_degree, s.num_extra);
    const DeviceSplatGradients g = arrays.View();
    // Garbage first: every value must be written.
    const std::pair<double*, size_t> outputs[] = {
        {g.means, got.means.size()},
        {g.log_scales, got.log_scales.size()},
        {g.quats, got.quats.size()},
        {g.opacity_logits, got.opacity_logits.size()},
        {g.sh, got.sh.size()},
        {g.extra, got.extra.size()}};
    for (const auto& [array, size] : outputs) {
      const std::vector<double> garbage(size, 12345.0);
      CopyToDevice(array, garbage.data(), size * sizeof(double));
    }
    ProjectBackward(d.in, s.count, s.num_extra, tiles.data(),
                    dev_grad2d.data(),
                    {g.means, g.log_scales, g.quats, g.opacity_logits, g.sh},
                    g.extra);
    arrays.Download(&got);
    for (int n = 0; n < s.count; ++n) {
      if (keep[n]) continue;  // the CPU kernel leaves culled rows alone
      for (int k = 0; k < 3; ++k) want.means[3 * n + k] = 0;
      for (int k = 0; k < 3; ++k) want.log_scales[3 * n + k] = 0;
      for (int k = 0; k < 4; ++k) want.quats[4 * n + k] = 0;
      want.opacity_logits[n] = 0;
      const int coeffs = 3 * NumShCoeffs(s.sh_degree);
      for (int k = 0; k < coeffs; ++k) want.sh[coeffs * n + k] = 0;
    }
    // Float rounding apart (fused multiply-adds differ): 1e-4 of the
    // largest entry, where a wrong term is of the order of that entry.
    ExpectGradientsClose(got, want, 1e-4, 0.0);
  }
}

TEST(CudaBinTest, TilesListTheirGaussiansFrontToBack) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const BenchScene scene = MakeScene(200, 150, 10000);
  TestScene s;
  s.camera = scene.camera;
  s.count = scene.gaussians.size();
  s.sh_degree = scene.gaussians.sh_degree;
  s.means = scene.gaussians.means;
  s.log_scales = scene.gaussians.log_scales;
  s.quats = scene.gaussians.quats;
  s.opacity_logits = scene.gaussians.opacity_logits;
  s.sh = scene.gaussians.sh;
  DeviceScene d(s);
  DeviceBuffer<ProjectedGaussian> projected(s.count);
  DeviceBuffer<float> features(4 * static_cast<size_t>(s.count));
  DeviceBuffer<int> tiles(s.count), visible(1);
  ProjectForward(d.in, s.count, 0, nullptr, projected.data(),
                 features.data(), tiles.data(), visible.data());
  const int tiles_x = d.in.tiles_x, tiles_y = d.in.tiles_y;
  BinScratch scratch;
  DeviceBuffer<int> gaussians;
  DeviceBuffer<int> ranges(2 * tiles_x * tiles_y);
  const int entries = BinGaussians(s.count, tiles_x, tiles_y,
                                   projected.data(), tiles.data(), &scratch,
                                   &gaussians, ranges.data());
  // The expected lists from the device's own projection: per tile, its
  // Gaussians by float depth, ties by index (the CPU's order).
  const std::vector<ProjectedGaussian> p = projected.Download();
  const std::vector<int> counts = tiles.Download();
  std::vector<int> order;
  for (int n = 0; n < s.count; ++n)
    if (counts[n] > 0) order.push_back(n);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return p[a].depth < p[b].depth; });
  std::vector<std::vector<int>> want(tiles_x * tiles_y);
  int total = 0;
  for (int n : order) {
    for (int ty = p[n].tile_y0; ty < p[n].tile_y1; ++ty)
      for (int tx = p[n].tile_x0; tx < p[n].tile_x1; ++tx, ++total)
        want[ty * tiles_x + tx].push_back(n);
  }
  ASSERT_EQ(entries, total);
  const std::vector<int> list = gaussians.Download();
  const std::vector<int> r = ranges.Download();
  size_t longest = 0;
  for (int t = 0; t < tiles_x * tiles_y; ++t) {
    const std::vector<int> got(list.begin() + r[2 * t],
                               list.begin() + r[2 * t + 1]);
    EXPECT_EQ(got, want[t]) << "tile " << t;
    longest = std::max(longest, want[t].size());
  }
  EXPECT_GT(longest, 256u) << "some tile should span several batches";
}

TEST(CudaBinTest, NoGaussiansAndNoVisibleOnes) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  TestScene empty = RandomScene(1, 0, 0, 0);
  Frames f = RenderBoth(empty.camera, empty.View(), 1);
  ExpectFramesMatch(f);
  for (double v : f.gpu.images.alpha) EXPECT_EQ(v, 0.0);
  // Every Gaussian behind the camera.
  TestScene behind = RandomScene(2, 0, 1, 1);
  for (int i = 0; i < 20; ++i) {
    behind.Add(behind.camera.Unproject(10 + i, 12, -2.0 - i),
               Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector4d(1, 0, 0, 0), 2);
  }
  f = RenderBoth(behind.camera, behind.View(), 2);
  EXPECT_EQ(f.gpu.visible, 0);
  ExpectFramesMatch(f);
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(f.gpu.images.rgb[c], reference::kTestBackground[c]);
}

// ---------------------------------------------------------- whole frames

class CudaFrameTest : public ::testing::TestWithParam<int> {};

TEST_P(CudaFrameTest, RandomScenesMatchCpu) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const int degree = GetParam();
  for (int num_extra : {0, 1, 2}) {
    SCOPED_TRACE("extras " + std::to_string(num_extra));
    const TestScene s = RandomScene(200 + degree, 40, degree, num_extra);
    ExpectFramesMatch(RenderBoth(s.camera, s.View(), 11 + num_extra));
  }
}

TEST_P(CudaFrameTest, OpaqueStackMatchesCpu) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const TestScene s = StackedScene(4, GetParam());
  const Frames f = RenderBoth(s.camera, s.View(), 5);
  double peak = 0;
  for (double a : f.cpu.images.alpha) peak = std::max(peak, a);
  EXPECT_GT(peak, 0.99) << "the stack should run the transmittance out";
  ExpectFramesMatch(f);
}

INSTANTIATE_TEST_SUITE_P(ShDegrees, CudaFrameTest,
                         ::testing::Values(0, 1, 2, 3));

TEST(CudaFrameTest, NeedlesAndTileCornersMatchCpu) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const TestScene s = NeedleScene();
  ExpectFramesMatch(RenderBoth(s.camera, s.View(), 6));
}

TEST(CudaFrameTest, MostExtraChannelsMatchCpu) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const TestScene s = RandomScene(300, 30, 1, kMaxDeviceExtra);
  ExpectFramesMatch(RenderBoth(s.camera, s.View(), 7));
}

// The benchmarks' scene, small: hundreds of Gaussians per tile (several
// batches of the tile passes), SH degree 3, one extra channel. At this
// size summation order and cut-off flips show in a few entries.
TEST(CudaFrameTest, DenseSceneMatchesCpu) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const BenchScene scene = MakeScene(200, 150, 10000);
  ExpectFramesMatch(RenderBoth(scene.camera, scene.View(), 8));
}

// ForwardDevice / BackwardDevice on device arrays give what the host
// interface gives (it runs them).
TEST(CudaFrameTest, DeviceInterfaceMatchesHostInterface) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  const TestScene s = RandomScene(400, 40, 2, 1);
  const int pixels = s.camera.width * s.camera.height;
  const ImageWeights w(pixels, 1, 9);
  DeviceRasterizer host;
  RenderResult host_images;
  SplatGradients host_grads;
  host.Forward(s.camera, s.View(), reference::TestRenderOptions(),
               &host_images);
  host.Backward(w.View(), &host_grads);

  const DeviceScene d(s);
  const DeviceSplatView view = d.splats.View();
  DeviceRasterizer device;
  const DeviceImages& images =
      device.ForwardDevice(s.camera, view, reference::kTestBackground);
  ASSERT_EQ(images.width, s.camera.width);
  std::vector<float> rgb(3 * pixels);
  CopyToHost(rgb.data(), images.rgb, rgb.size() * sizeof(float));
  for (int i = 0; i < 3 * pixels; ++i)
    ASSERT_EQ(rgb[i], static_cast<float>(host_images.rgb[i])) << i;
  const auto as_float = [](const std::vector<double>& v) {
    DeviceBuffer<float> b;
    b.Upload(std::vector<float>(v.begin(), v.end()));
    return b;
  };
  const DeviceBuffer<float> d_rgb = as_float(w.rgb),
                            d_alpha = as_float(w.alpha),
                            d_depth = as_float(w.depth),
                            d_extra = as_float(w.extra);
  DeviceGradientArrays arrays;
  arrays.Resize(s.count, s.sh_degree, s.num_extra);
  device.BackwardDevice({d_rgb.data(), d_alpha.data(), d_depth.data(),
                         d_extra.data()},
                        arrays.View());
  // Atomic sums may add in another order: float rounding apart.
  SplatGradients got;
  arrays.Download(&got);
  ExpectGradientsClose(got, host_grads, 1e-5, 0.0);
}

// ------------------------------------------------------------- errors

TEST(CudaErrorTest, DeviceStatusExplainsItself) {
  std::string why;
  const bool available = CudaDeviceAvailable(&why);
  EXPECT_FALSE(why.empty());
  if (available) {
    EXPECT_NE(why.find("sm_"), std::string::npos) << why;
  }
}

TEST(CudaErrorTest, FailedCallsThrowWithPlaceAndCause) {
  ES_REQUIRE_GPU("CUDA rasterizer");
  try {
    DeviceAllocate(size_t{1} << 52);  // 4 PiB
    FAIL() << "expected a CudaError";
  } catch (const CudaError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("device_buffer.cc"), std::string::npos) << what;
    EXPECT_NE(what.find("cudaMalloc"), std::string::npos) << what;
  }
  // The failure is cleared: the next work runs.
  const TestScene s = RandomScene(500, 10, 0, 0);
  ExpectFramesMatch(RenderBoth(s.camera, s.View(), 1));
}

}  // namespace
}  // namespace cuda
}  // namespace es
