// Triplane sampling and its backward on the device, one thread per point,
// with Triplane's arithmetic (core/fields/triplane.cc) in double: the same
// align-corners texel mapping, border clamp and NaN rule.

#include "core/fields/cuda/field_kernels.h"
#include "core/base/cuda/cuda_check.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 128;
constexpr int kSum = 0, kProduct = 1;  // PlaneCombination's order
// Axes (column, row) of each plane: xy, xz, yz.
__device__ const int kPlaneAxes[3][2] = {{0, 1}, {0, 2}, {1, 2}};

struct AxisSample {
  int i0;        // lower texel
  double frac;   // weight of texel i0 + 1
  double ds_dx;  // d frac / d x; 0 where clamped
};

__device__ AxisSample SampleAxis(const TriplaneGeometry& g, double x,
                                 int axis) {
  const int last = g.resolution - 1;
  const double s = (x - g.lo[axis]) * g.texels_per_unit[axis];
  // Written so that NaN lands in the first branch.
  if (!(s > 0.0)) return {0, 0.0, 0.0};
  if (s >= last) return {last - 1, 1.0, 0.0};
  const int i0 = min(static_cast<int>(s), last - 1);
  return {i0, s - i0, g.texels_per_unit[axis]};
}

// One plane's bilinear sample at a point.
struct PlaneSample {
  AxisSample a, b;   // column and row axes
  long long t00;     // offset of texel (a.i0, b.i0), channel 0
};

__device__ PlaneSample SamplePlane(const TriplaneGeometry& g,
                                   const double* x, int p) {
  PlaneSample s;
  s.a = SampleAxis(g, x[kPlaneAxes[p][0]], kPlaneAxes[p][0]);
  s.b = SampleAxis(g, x[kPlaneAxes[p][1]], kPlaneAxes[p][1]);
  const long long r = g.resolution;
  s.t00 = ((p * r + s.b.i0) * r + s.a.i0) * g.channels;
  return s;
}

// Channel k of the plane's feature.
__device__ double Feature(const TriplaneGeometry& g, const double* params,
                          const PlaneSample& s, int k) {
  const long long c = g.channels, rc = g.resolution * c;
  const double* t00 = params + s.t00;
  const double fa = s.a.frac, fb = s.b.frac;
  return (1 - fa) * (1 - fb) * t00[k] + fa * (1 - fb) * t00[k + c] +
         (1 - fa) * fb * t00[k + rc] + fa * fb * t00[k + rc + c];
}

__global__ void SampleKernel(TriplaneGeometry g, const double* params, int n,
                             const double* x, double* out, int out_stride) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double* xi = x + 3LL * i;
  double* o = out + static_cast<long long>(out_stride) * i;
  const int c = g.channels;
  for (int p = 0; p < 3; ++p) {
    const PlaneSample s = SamplePlane(g, xi, p);
    for (int k = 0; k < c; ++k) {
      const double f = Feature(g, params, s, k);
      if (g.combination == kSum) {
        o[k] = p == 0 ? f : o[k] + f;
      } else if (g.combination == kProduct) {
        o[k] = p == 0 ? f : o[k] * f;
      } else {
        o[p * c + k] = f;
      }
    }
  }
}

__global__ void BackwardKernel(TriplaneGeometry g, const double* params,
                               int n, const double* x, const double* d_out,
                               int d_out_stride, double* d_params,
                               double* d_x) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double* xi = x + 3LL * i;
  const double* go = d_out + static_cast<long long>(d_out_stride) * i;
  const long long c = g.channels, rc = g.resolution * c;
  PlaneSample planes[3];
  for (int p = 0; p < 3; ++p) planes[p] = SamplePlane(g, xi, p);
  for (int p = 0; p < 3; ++p) {
    const PlaneSample& s = planes[p];
    const double fa = s.a.frac, fb = s.b.frac;
    const double* t00 = params + s.t00;
    double d_a = 0.0, d_b = 0.0;
    for (int k = 0; k < c; ++k) {
      // dL / d(this plane's feature k).
      double gk;
      if (g.combination == kSum) {
        gk = go[k];
      } else if (g.combination == kProduct) {
        gk = go[k] * Feature(g, params, planes[(p + 1) % 3], k) *
             Feature(g, params, planes[(p + 2) % 3], k);
      } else {
        gk = go[p * c + k];
      }
      const double v00 = t00[k], v01 = t00[k + c];
      const double v10 = t00[k + rc], v11 = t00[k + rc + c];
      d_a += gk * ((1 - fb) * (v01 - v00) + fb * (v11 - v10));
      d_b += gk * ((1 - fa) * (v10 - v00) + fa * (v11 - v01));
      if (d_params != nullptr) {
        double* g00 = d_params + s.t00;
        atomicAdd(g00 + k, (1 - fa) * (1 - fb) * gk);
        atomicAdd(g00 + k + c, fa * (1 - fb) * gk);
        atomicAdd(g00 + k + rc, (1 - fa) * fb * gk);
        atomicAdd(g00 + k + rc + c, fa * fb * gk);
      }
    }
    if (d_x != nullptr) {
      d_x[3LL * i + kPlaneAxes[p][0]] += s.a.ds_dx * d_a;
      d_x[3LL * i + kPlaneAxes[p][1]] += s.b.ds_dx * d_b;
    }
  }
}

int Blocks(int n) { return (n + kThreads - 1) / kThreads; }

}  // namespace

void TriplaneSampleKernel(const TriplaneGeometry& g, const double* params,
                          int n, const double* x, double* out,
                          int out_stride) {
  if (n == 0) return;
  SampleKernel<<<Blocks(n), kThreads>>>(g, params, n, x, out, out_stride);
  ES_CUDA_CHECK_LAUNCH("TriplaneSampleKernel");
}

void TriplaneBackwardKernel(const TriplaneGeometry& g, const double* params,
                            int n, const double* x, const double* d_out,
                            int d_out_stride, double* d_params, double* d_x) {
  if (n == 0 || (d_params == nullptr && d_x == nullptr)) return;
  BackwardKernel<<<Blocks(n), kThreads>>>(g, params, n, x, d_out,
                                          d_out_stride, d_params, d_x);
  ES_CUDA_CHECK_LAUNCH("TriplaneBackwardKernel");
}

}  // namespace cuda
}  // namespace es
