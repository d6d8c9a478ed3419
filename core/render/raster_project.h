#ifndef EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_
#define EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/render/rasterizer.h"

namespace es {

// The camera quantities the per-Gaussian projection needs, computed once.
struct ProjectionCamera {
  Eigen::Matrix3d R;       // world -> camera rotation
  Eigen::Vector3d t;       // world -> camera translation
  Eigen::Vector3d center;  // camera center in world
  double fx, fy, cx, cy;
  double lim_x, lim_y;     // FOV clamp of x/z and y/z: 1.3 * tan(fov / 2)
  int width, height, tiles_x, tiles_y;

  explicit ProjectionCamera(const Camera& camera);
};

// One Gaussian after projection, everything the tile pass needs.
struct ProjectedSplat {
  double mean2d[2];  // continuous pixel coordinates
  double conic[3];   // inverse of the dilated 2D covariance: a, b, c
  double depth;      // camera z
  double opacity;
  double color[3];   // SH + 0.5, clamped below at 0
  int radius;        // ceil(3 sqrt(max eigenvalue)), px
  // Tiles [tile_x0, tile_x1) x [tile_y0, tile_y1) the Gaussian is binned to:
  // those its 3-sigma square touches and its pixel box reaches.
  int tile_x0, tile_x1, tile_y0, tile_y1;
  // Pixels [px0, px1) x [py0, py1) that can reach alpha >= kMinAlpha, with a
  // one-pixel margin; outside it the tile pass skips the Gaussian.
  int px0, px1, py0, py1;
};

// Projects Gaussian n; returns false if it is culled (behind the near plane,
// degenerate, off-screen, too transparent, or non-finite).
bool ProjectSplat(const ProjectionCamera& camera, const SplatView& splats,
                  int n, ProjectedSplat* out);

// Gradients of the loss with respect to one Gaussian's projected quantities,
// as the tile pass accumulates them.
struct ProjectedGradient {
  double mean2d[2] = {0, 0};
  double conic[3] = {0, 0, 0};  // d/da, d/db, d/dc with sigma =
                                // 0.5 (a dx^2 + c dy^2) + b dx dy
  double opacity = 0;
  double color[3] = {0, 0, 0};  // w.r.t. the clamped color
  double depth = 0;
};

// Chains `g` back to Gaussian n's means, log-scales, quaternions, opacity
// logit and SH, writing (not adding) those entries of `grads`.
void ProjectSplatBackward(const ProjectionCamera& camera,
                          const SplatView& splats, int n,
                          const ProjectedGradient& g, SplatGradients* grads);

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_
