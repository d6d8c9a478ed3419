#ifndef EULERSPLAT_CORE_LOOP_CUDA_EULER_KERNELS_H_
#define EULERSPLAT_CORE_LOOP_CUDA_EULER_KERNELS_H_

// The Euler chain's per-point kernels (euler.cu), as DeviceEulerChain
// launches them. Points are in the chain's sorted order (most steps
// first); order[k] is sorted point k's index in the caller's arrays. Plain
// types only; all pointers are device pointers, positions n x 3 doubles.

namespace es {
namespace cuda {

// Indices into the step counters.
constexpr int kClampedSteps = 0;
constexpr int kNonFiniteVelocities = 1;

// Sorted point k < first (it takes steps) to trajectory row k, the others
// straight to x_out[order[k]].
void EulerStartKernel(int n, int first, const int* order, const double* x0,
                      double* trajectory, double* x_out);
// One step of the m active points at xs with velocities v, by
// TakeSafeStep's rule: to next row k while k < m_next (the point steps
// again), else to x_out[order[k]]; counts clamped and non-finite steps
// into counters (unsigned long long[2]).
void EulerStepKernel(int m, int m_next, const int* order, const double* xs,
                     const double* v, double max_step, double* next,
                     double* x_out, unsigned long long* counters);
// gradient row k = d_x_out[order[k]].
void EulerGatherKernel(int n, const int* order, const double* d_x_out,
                       double* gradient);
// step_gradient = J^T gradient for the step function at velocity v, m rows.
void EulerStepBackwardKernel(int m, const double* v, double max_step,
                             const double* gradient, double* step_gradient);
// Alg. 2's step of n points (LoopAnimator::Advance): cycle_index[k] + 1,
// and at cycle_length back to 0 with the point reset to canonical[k];
// otherwise the point takes the step of velocity v[k], counted as in
// EulerStepKernel.
void EulerAdvanceKernel(int n, int cycle_length, const double* v,
                        double max_step, const double* canonical,
                        double* positions, int* cycle_index,
                        unsigned long long* counters);
// to = from, count doubles.
void CopyDoublesKernel(long long count, const double* from, double* to);
// d_x0[order[k]] += gradient row k.
void EulerScatterAddKernel(int n, const int* order, const double* gradient,
                           double* d_x0);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_EULER_KERNELS_H_
