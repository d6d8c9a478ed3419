// The Euler chain's per-point work on the device, one thread per point:
// the stress rule of EulerOptions and its Jacobian (core/loop/safe_step.h,
// which EulerChain runs too), in double, and Alg. 2's step
// (LoopAnimator::Advance).

#include "core/loop/cuda/euler_kernels.h"
#include "core/base/cuda/cuda_check.h"
#include "core/loop/safe_step.h"

namespace es {
namespace cuda {
namespace {

constexpr int kThreads = 128;

int Blocks(int n) { return (n + kThreads - 1) / kThreads; }

// Counts a clamped or non-finite step (EulerStats).
__device__ void Count(StepKind kind, unsigned long long* counters) {
  if (kind == StepKind::kClamped) atomicAdd(counters + kClampedSteps, 1ULL);
  if (kind == StepKind::kNonFinite)
    atomicAdd(counters + kNonFiniteVelocities, 1ULL);
}

__global__ void StartKernel(int n, int first, const int* order,
                            const double* x0, double* trajectory,
                            double* x_out) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  const double* src = x0 + 3LL * order[k];
  double* dst = k < first ? trajectory + 3LL * k : x_out + 3LL * order[k];
  for (int j = 0; j < 3; ++j) dst[j] = src[j];
}

__global__ void StepKernel(int m, int m_next, const int* order,
                           const double* xs, const double* v,
                           double max_step, double* next, double* x_out,
                           unsigned long long* counters) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  double step[3];
  Count(SafeStep(v + 3LL * k, max_step, step), counters);
  double* dst = k < m_next ? next + 3LL * k : x_out + 3LL * order[k];
  for (int j = 0; j < 3; ++j) dst[j] = xs[3LL * k + j] + step[j];
}

__global__ void AdvanceKernel(int n, int cycle_length, const double* v,
                              double max_step, const double* canonical,
                              double* positions, int* cycle_index,
                              unsigned long long* counters) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  double* x = positions + 3LL * k;
  if (++cycle_index[k] == cycle_length) {
    cycle_index[k] = 0;
    for (int j = 0; j < 3; ++j) x[j] = canonical[3LL * k + j];
    return;
  }
  double step[3];
  Count(SafeStep(v + 3LL * k, max_step, step), counters);
  for (int j = 0; j < 3; ++j) x[j] += step[j];
}

__global__ void CopyKernel(long long count, const double* from, double* to) {
  const long long i = static_cast<long long>(blockIdx.x) * blockDim.x +
                      threadIdx.x;
  if (i < count) to[i] = from[i];
}

__global__ void GatherKernel(int n, const int* order, const double* d_x_out,
                             double* gradient) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  for (int j = 0; j < 3; ++j) {
    gradient[3LL * k + j] = d_x_out[3LL * order[k] + j];
  }
}

// d_v = J^T g for the step function of SafeStep at v.
__global__ void StepBackwardKernel(int m, const double* velocity,
                                   double max_step, const double* gradient,
                                   double* step_gradient) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= m) return;
  SafeStepBackward(velocity + 3LL * k, max_step, gradient + 3LL * k,
                   step_gradient + 3LL * k);
}

__global__ void ScatterAddKernel(int n, const int* order,
                                 const double* gradient, double* d_x0) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  for (int j = 0; j < 3; ++j) {
    d_x0[3LL * order[k] + j] += gradient[3LL * k + j];
  }
}

}  // namespace

void EulerStartKernel(int n, int first, const int* order, const double* x0,
                      double* trajectory, double* x_out) {
  if (n == 0) return;
  StartKernel<<<Blocks(n), kThreads>>>(n, first, order, x0, trajectory,
                                       x_out);
  ES_CUDA_CHECK_LAUNCH("EulerStartKernel");
}

void EulerStepKernel(int m, int m_next, const int* order, const double* xs,
                     const double* v, double max_step, double* next,
                     double* x_out, unsigned long long* counters) {
  if (m == 0) return;
  StepKernel<<<Blocks(m), kThreads>>>(m, m_next, order, xs, v, max_step,
                                      next, x_out, counters);
  ES_CUDA_CHECK_LAUNCH("EulerStepKernel");
}

void EulerAdvanceKernel(int n, int cycle_length, const double* v,
                        double max_step, const double* canonical,
                        double* positions, int* cycle_index,
                        unsigned long long* counters) {
  if (n == 0) return;
  AdvanceKernel<<<Blocks(n), kThreads>>>(n, cycle_length, v, max_step,
                                         canonical, positions, cycle_index,
                                         counters);
  ES_CUDA_CHECK_LAUNCH("EulerAdvanceKernel");
}

void CopyDoublesKernel(long long count, const double* from, double* to) {
  if (count == 0) return;
  const int blocks = static_cast<int>((count + kThreads - 1) / kThreads);
  CopyKernel<<<blocks, kThreads>>>(count, from, to);
  ES_CUDA_CHECK_LAUNCH("CopyDoublesKernel");
}

void EulerGatherKernel(int n, const int* order, const double* d_x_out,
                       double* gradient) {
  if (n == 0) return;
  GatherKernel<<<Blocks(n), kThreads>>>(n, order, d_x_out, gradient);
  ES_CUDA_CHECK_LAUNCH("EulerGatherKernel");
}

void EulerStepBackwardKernel(int m, const double* v, double max_step,
                             const double* gradient, double* step_gradient) {
  if (m == 0) return;
  StepBackwardKernel<<<Blocks(m), kThreads>>>(m, v, max_step, gradient,
                                              step_gradient);
  ES_CUDA_CHECK_LAUNCH("EulerStepBackwardKernel");
}

void EulerScatterAddKernel(int n, const int* order, const double* gradient,
                           double* d_x0) {
  if (n == 0) return;
  ScatterAddKernel<<<Blocks(n), kThreads>>>(n, order, gradient, d_x0);
  ES_CUDA_CHECK_LAUNCH("EulerScatterAddKernel");
}

}  // namespace cuda
}  // namespace es
