// Per-Gaussian screen statistics of the last render copied into device
// arrays, as DeviceRasterizer::Radii and Mean2dGradients read them on the
// host: one thread per Gaussian.

#include "core/base/cuda/cuda_check.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 256;

int Blocks(int count) { return (count + kThreads - 1) / kThreads; }

__global__ void RadiiKernel(int count, const ProjectedGaussian* projected,
                            int* radii) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n < count) radii[n] = projected[n].radius;
}

__global__ void Mean2dKernel(int count, const int* tiles,
                             const double* grad2d, int stride,
                             double* mean2d_grads) {
  const int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= count) return;
  const bool binned = tiles[n] != 0;
  const double* row = grad2d + static_cast<long long>(stride) * n;
  mean2d_grads[2 * n] = binned ? row[0] : 0.0;
  mean2d_grads[2 * n + 1] = binned ? row[1] : 0.0;
}

}  // namespace

void CopyRadii(int count, const ProjectedGaussian* projected, int* radii) {
  if (count == 0) return;
  RadiiKernel<<<Blocks(count), kThreads>>>(count, projected, radii);
  ES_CUDA_CHECK_LAUNCH("RadiiKernel");
}

void CopyMean2dGradients(int count, const int* tiles, const double* grad2d,
                         int stride, double* mean2d_grads) {
  if (count == 0) return;
  Mean2dKernel<<<Blocks(count), kThreads>>>(count, tiles, grad2d, stride,
                                            mean2d_grads);
  ES_CUDA_CHECK_LAUNCH("Mean2dKernel");
}

}  // namespace cuda
}  // namespace es
