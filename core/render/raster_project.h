#ifndef EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_
#define EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_

#include <Eigen/Core>

#include "core/model/camera.h"
#include "core/render/project_kernels.h"
#include "core/render/splat_view.h"

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

// Projects Gaussian n in double; returns false if it is culled (behind the
// near plane, degenerate, off-screen, too transparent, or non-finite). The
// reference the float kernels of project_kernels.h are tested against; the
// rasterizer runs it with RenderOptions::use_double.
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

// The batched float kernels' view of a camera and splats
// (project_kernels.h), and of the gradients they write.
ProjectionInput MakeProjectionInput(const ProjectionCamera& camera,
                                    const SplatView& splats);
ProjectionGradients MakeProjectionGradients(SplatGradients* grads);

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RASTER_PROJECT_H_
