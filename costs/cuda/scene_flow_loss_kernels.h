#ifndef EULERSPLAT_COSTS_CUDA_SCENE_FLOW_LOSS_KERNELS_H_
#define EULERSPLAT_COSTS_CUDA_SCENE_FLOW_LOSS_KERNELS_H_

// The device scene-flow loss's kernels (scene_flow_loss.cu): plain types only,
// device pointers.

namespace es {
namespace cuda {

// Row k < n of x, target and unseen (n x 3) = row indices[k] of samples_x,
// samples_v and samples_unseen (num_samples x 3).
void GatherSceneFlowBatch(int n, const int* indices, const double* samples_x,
                          const double* samples_v,
                          const double* samples_unseen, double* x,
                          double* target, double* unseen);
// Row s < n of d (n x 3) -= (d_s . u_s) u_s, u_s row s of unseen (|u_s| <=
// 1): SceneFlowCost's projection P_s.
void ProjectOutUnseen(int n, const double* unseen, double* d);
// Row s < n of v (n x 3) = P_s (v_s - target_s) in one pass.
void ConstrainedDifference(int n, const double* target, const double* unseen,
                           double* v);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_SCENE_FLOW_LOSS_KERNELS_H_
