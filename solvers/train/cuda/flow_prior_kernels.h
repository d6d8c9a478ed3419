#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_FLOW_PRIOR_KERNELS_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_FLOW_PRIOR_KERNELS_H_

// The device scene-flow prior's kernels (flow_prior.cu): plain types only,
// device pointers.

namespace es {
namespace cuda {

// Row k < n of x and target (n x 3) = row indices[k] of samples_x and
// samples_v (num_samples x 3).
void GatherSceneFlowBatch(int n, const int* indices, const double* samples_x,
                          const double* samples_v, double* x, double* target);
// v -= target over n values.
void SubtractTarget(long long n, const double* target, double* v);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_FLOW_PRIOR_KERNELS_H_
