// The residual field's encodings of cycle index and cycle number
// (EncodeSinusoidal, core/fields/positional_encoding.h) on the device, in
// double, into the MLP input rows next to the triplane features.

#include "core/fields/cuda/field_kernels.h"
#include "core/base/cuda/cuda_check.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 128;
constexpr double kPi = 3.14159265358979323846;  // M_PI

__device__ void Encode(double value, int num_frequencies, double period,
                       double* out) {
  double angle = 2.0 * kPi * value / period;
  for (int k = 0; k < num_frequencies; ++k) {
    out[2 * k] = sin(angle);
    out[2 * k + 1] = cos(angle);
    angle *= 2.0;
  }
}

__global__ void EncodeKernel(int n, const int* t, const int* p,
                             int t_frequencies, double t_period,
                             int p_frequencies, double p_period, double* rows,
                             int stride, int column) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  double* row = rows + static_cast<long long>(stride) * i + column;
  Encode(t[i], t_frequencies, t_period, row);
  Encode(p[i], p_frequencies, p_period, row + 2 * t_frequencies);
}

}  // namespace

void EncodeCycleKernel(int n, const int* t, const int* p, int t_frequencies,
                       double t_period, int p_frequencies, double p_period,
                       double* rows, int stride, int column) {
  if (n == 0) return;
  EncodeKernel<<<(n + kThreads - 1) / kThreads, kThreads>>>(
      n, t, p, t_frequencies, t_period, p_frequencies, p_period, rows, stride,
      column);
  ES_CUDA_CHECK_LAUNCH("EncodeCycleKernel");
}

}  // namespace cuda
}  // namespace es
