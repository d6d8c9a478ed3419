#ifndef EULERSPLAT_CORE_RENDER_RASTERIZER_H_
#define EULERSPLAT_CORE_RENDER_RASTERIZER_H_

#include <vector>

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/model/gaussians.h"
#include "core/render/raster_constants.h"
#include "core/render/splat_view.h"
#include "core/render/tile_kernels.h"

namespace es {

struct RenderOptions {
  Eigen::Vector3d background = Eigen::Vector3d::Zero();
  // Compute the projection (the double reference, raster_project.h) and
  // the tile loops in double (for tests); float runs the projection
  // kernels of project_kernels.h.
  bool use_double = false;
  // Instruction set of the tile and projection kernels (kAuto: the best
  // the CPU has).
  SimdLevel simd = SimdLevel::kAuto;
};

// Row-major images, H x W (x channels).
struct RenderResult {
  int width = 0, height = 0;
  std::vector<double> rgb;    // H*W*3, includes background * T_final
  std::vector<double> alpha;  // H*W, 1 - T_final
  std::vector<double> depth;  // H*W, sum_i w_i z_i (divide by alpha for the
                              // expected depth of the visible surface)
  std::vector<double> extra;  // H*W*E, sum_i w_i extra_i (no background)
};

// Image-space gradients of a loss; nullptr means zero.
struct RenderGradients {
  const double* d_rgb = nullptr;
  const double* d_alpha = nullptr;
  const double* d_depth = nullptr;
  const double* d_extra = nullptr;
};

// Tile-based EWA splatting, forward and analytic backward, parallel over
// tiles (OpenMP). Keeps the per-Gaussian and per-pixel state of the last
// Forward (and its buffers, reused to avoid allocation), so Backward must
// follow Forward on the same object with the same camera, splats and
// options; the arrays the SplatView points at must stay alive and unchanged
// in between. Conventions: see core/render/raster_project.h (projection,
// culling, FOV clamp) and core/render/rasterizer.cc (compositing); the test
// twin is tests/reference_rasterizer.h.
class Rasterizer {
 public:
  Rasterizer();
  ~Rasterizer();
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;

  void Forward(const Camera& camera, const SplatView& splats,
               const RenderOptions& options, RenderResult* result);
  // Overwrites *grads with d loss / d splat attributes.
  void Backward(const RenderGradients& image_grads, SplatGradients* grads);

  // Number of Gaussians that survived culling in the last Forward.
  int num_visible() const;
  // Gaussian-pixel pairs the last Forward looked at (its work, for
  // benchmarks): each binned Gaussian's pixel box within each of its tiles.
  long long num_pair_evaluations() const;
  // Per input Gaussian, from the last Forward: its screen radius in pixels,
  // ceil(3 sqrt(largest eigenvalue of the 2D covariance)), 0 if culled.
  void Radii(std::vector<int>* radii) const;
  // Per input Gaussian, from the last Backward: d loss / d projected mean in
  // pixels (u, v), 0 if culled: the view-space gradient 3DGS densification
  // accumulates (2N).
  void Mean2dGradients(std::vector<double>* grads) const;

 private:
  struct State;
  State* state_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RASTERIZER_H_
