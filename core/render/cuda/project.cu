// The projection of Gaussians to the screen and its backward on the device,
// one thread per Gaussian: the per-Gaussian maths of
// core/render/projection_math.inc, which the CPU's float kernels
// (project_kernels_impl.h) run too, with one lane (B = 1) and the library
// exp and log where the CPU has its own polynomials.

#include "core/base/cuda/cuda_check.h"
#include "core/base/host_device.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

ES_HOST_DEVICE inline float Exp(
    float x) {  // the CPU clamps to the normal range
  x = x > -87.0f ? x : -87.0f;
  return expf(x < 88.0f ? x : 88.0f);
}
ES_HOST_DEVICE inline float Log(float x) { return logf(x); }
ES_HOST_DEVICE inline float Sqrt(float x) { return sqrtf(x); }

#include "core/render/projection_math.inc"

// color[ch] = 0.5 + sum_k basis[k] sh[3k + ch] before the clamp at 0.
__device__ void ShColor(const ProjectionInput& in, int n, int coeffs,
                        const F basis[kMaxCoeffs][1], F color[3][1]) {
  const double* sh = in.sh + 3 * static_cast<size_t>(coeffs) * n;
  for (int ch = 0; ch < 3; ++ch) color[ch][0] = 0.5f;
  for (int k = 0; k < coeffs; ++k)
    for (int ch = 0; ch < 3; ++ch)
      color[ch][0] += basis[k][0] * static_cast<F>(sh[3 * k + ch]);
}

// Gaussian n's inputs, geometry, view direction, SH basis and colour.
struct Projection {
  Camera cam;
  Lanes<1> l;
  Geometry<1> g;
  F dir[3][1], len[1], basis[kMaxCoeffs][1], color[3][1];
  __device__ Projection(const ProjectionInput& in, int n, int coeffs)
      : cam(in) {
    GatherLane(in, n, 0, &l);
    GeometryLane(cam, l, 0, &g);
    ViewDirectionLane(l, 0, dir, len);
    ShBasisLane(dir, 0, basis);
    ShColor(in, n, coeffs, basis, color);
  }
};

__global__ void ProjectKernel(ProjectionInput in, int count, int num_extra,
                              const double* extra, ProjectedGaussian* projected,
                              float* features, int* tiles, int* visible) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  const Projection pr(in, n, coeffs);
  Footprint<1> fp;
  FootprintLane(pr.cam, pr.l, pr.g, pr.color, 0, &fp);
  const bool keep = fp.ok[0] != 0.0f;
  ProjectedGaussian p;
  p.mean[0] = fp.mean[0][0];
  p.mean[1] = fp.mean[1][0];
  for (int k = 0; k < 3; ++k) p.conic[k] = static_cast<F>(pr.g.conic[k][0]);
  p.opacity = fp.opacity[0];
  p.depth = pr.l.p[2][0];
  p.radius = keep ? static_cast<int>(fp.radius[0]) : 0;
  p.px0 = fp.box[0][0];
  p.px1 = fp.box[1][0];
  p.py0 = fp.box[2][0];
  p.py1 = fp.box[3][0];
  p.tile_x0 = fp.box[4][0];
  p.tile_x1 = fp.box[5][0];
  p.tile_y0 = fp.box[6][0];
  p.tile_y1 = fp.box[7][0];
  projected[n] = p;
  tiles[n] = keep ? (p.tile_x1 - p.tile_x0) * (p.tile_y1 - p.tile_y0) : 0;
  if (!keep) return;
  atomicAdd(visible, 1);
  const int nf = 4 + num_extra;
  float* f = features + static_cast<size_t>(nf) * n;
  for (int ch = 0; ch < 3; ++ch) f[ch] = Max(pr.color[ch][0], 0.0f);
  f[3] = pr.l.p[2][0];
  for (int e = 0; e < num_extra; ++e)
    f[4 + e] = static_cast<F>(extra[static_cast<size_t>(num_extra) * n + e]);
}

__global__ void ProjectBackwardKernel(ProjectionInput in, int count,
                                      int num_extra, const int* tiles,
                                      const double* grad2d,
                                      ProjectionGradients out,
                                      double* d_extra) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const int coeffs = (in.sh_degree + 1) * (in.sh_degree + 1);
  const size_t un = static_cast<size_t>(n);
  double* g_sh = out.sh + 3 * static_cast<size_t>(coeffs) * un;
  if (tiles[n] == 0) {  // culled: zeros
    for (int k = 0; k < 3; ++k) out.means[3 * un + k] = 0;
    for (int k = 0; k < 3; ++k) out.log_scales[3 * un + k] = 0;
    for (int k = 0; k < 4; ++k) out.quats[4 * un + k] = 0;
    out.opacity_logits[n] = 0;
    for (int k = 0; k < 3 * coeffs; ++k) g_sh[k] = 0;
    for (int e = 0; e < num_extra; ++e) d_extra[num_extra * un + e] = 0;
    return;
  }
  const int stride = kTileGradHead + 4 + num_extra;
  const double* row = grad2d + static_cast<size_t>(stride) * un;
  for (int e = 0; e < num_extra; ++e)
    d_extra[num_extra * un + e] = row[kTileGradHead + 4 + e];
  const Projection pr(in, n, coeffs);
  ScreenGradients<1> sg;
  GatherGradientLane(row, 0, &sg);
  GeometryGradients<1> gg;
  GeometryBackwardLane(pr.cam, pr.l, pr.g, sg, 0, &gg);
  for (int k = 0; k < 3; ++k) out.log_scales[3 * un + k] = gg.log_scale[k][0];
  for (int k = 0; k < 4; ++k) out.quats[4 * un + k] = gg.quat[k][0];
  out.opacity_logits[n] = gg.logit[0];

  // Colour: SH + 0.5, clamped below at 0 (no gradient where clamped).
  F g_color[3];
  for (int ch = 0; ch < 3; ++ch)
    g_color[ch] = pr.color[ch][0] < 0 ? 0.0f : sg.pg[kTileGradHead + ch][0];
  const double* sh = in.sh + 3 * static_cast<size_t>(coeffs) * un;
  F g_basis[kMaxCoeffs][1];
  for (int k = 0; k < kMaxCoeffs; ++k) g_basis[k][0] = 0.0f;
  for (int k = 0; k < coeffs; ++k) {
    g_basis[k][0] = static_cast<F>(sh[3 * k]) * g_color[0] +
                    static_cast<F>(sh[3 * k + 1]) * g_color[1] +
                    static_cast<F>(sh[3 * k + 2]) * g_color[2];
    for (int ch = 0; ch < 3; ++ch)
      g_sh[3 * k + ch] = pr.basis[k][0] * g_color[ch];
  }
  if (in.sh_degree > 0)
    ViewDirectionBackwardLane(pr.dir, pr.len, g_basis, 0, gg.mean);
  for (int k = 0; k < 3; ++k) out.means[3 * un + k] = gg.mean[k][0];
}

int Blocks(int count) { return (count + kThreads - 1) / kThreads; }

}  // namespace

void ProjectForward(const ProjectionInput& in, int count, int num_extra,
                    const double* extra, ProjectedGaussian* projected,
                    float* features, int* tiles, int* visible) {
  ES_CUDA_CHECK(cudaMemset(visible, 0, sizeof(int)));
  if (count == 0) return;
  ProjectKernel<<<Blocks(count), kThreads>>>(
      in, count, num_extra, extra, projected, features, tiles, visible);
  ES_CUDA_CHECK_LAUNCH("ProjectKernel");
}

void ProjectBackward(const ProjectionInput& in, int count, int num_extra,
                     const int* tiles, const double* grad2d,
                     const ProjectionGradients& out, double* d_extra) {
  if (count == 0) return;
  ProjectBackwardKernel<<<Blocks(count), kThreads>>>(
      in, count, num_extra, tiles, grad2d, out, d_extra);
  ES_CUDA_CHECK_LAUNCH("ProjectBackwardKernel");
}

}  // namespace cuda
}  // namespace es
