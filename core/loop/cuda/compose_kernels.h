#ifndef EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_
#define EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_

// The frame composition kernels (compose.cu), forward as
// DeviceLoopRenderer and DeviceFrameComposer launch it and backward as
// DeviceFrameComposer does. Plain types only; all pointers are device
// pointers.

namespace es {
namespace cuda {

// Where D's outputs sit in one of its rows (core/fields/residual_field.h).
struct ResidualLayout {
  int dim = 0, position = 0, opacity = 0, sh = 0;
};

// SH coefficients per channel that D offsets: all its outputs past
// layout.sh, or fewer when the model has fewer (`coeffs`).
inline int OffsetShCoeffs(const ResidualLayout& layout, int coeffs) {
  const int offered = (layout.dim - layout.sh) / 3;
  return coeffs < offered ? coeffs : offered;
}

// FrameComposer's assembly of the m dynamic Gaussians into arrays that
// hold the canonical values: Gaussian n = dynamic[k] gets the mean
// positions[k] (+ D's position offset), and, with residuals set
// (m x layout.dim), D's opacity logit offset and its SH offsets for the
// first offset_coeffs coefficients of the `coeffs` per channel.
void ComposeDynamicKernel(int m, const int* dynamic, const double* positions,
                          const double* residuals,
                          const ResidualLayout& layout, int coeffs,
                          int offset_coeffs, double* means,
                          double* opacity_logits, double* sh);

// x0[k] = means[dynamic[k]] (rows of 3), k < m.
void GatherDynamicMeansKernel(int m, const int* dynamic, const double* means,
                              double* x0);

// The composition's backward for the dynamic Gaussians (FrameComposer::
// Backward): d_positions[k] = d_means[dynamic[k]], and, with d_residuals
// set (m x layout.dim), the gradient of D's outputs: the same mean
// gradient at the position offsets, d_opacity at the opacity offset, the
// first offset_coeffs of the `coeffs` SH coefficients per channel at the
// SH offsets, 0 elsewhere, plus extra_d_residuals (m x layout.dim,
// nullable) everywhere.
void ComposeBackwardKernel(int m, const int* dynamic, const double* d_means,
                           const double* d_opacity, const double* d_sh,
                           const ResidualLayout& layout, int coeffs,
                           int offset_coeffs, const double* extra_d_residuals,
                           double* d_positions, double* d_residuals);

// The means' gradient rows of `count` Gaussians, added (+=) into out:
// d_means[n] for a static Gaussian (slot[n] < 0), d_x0[slot[n]] for a
// dynamic one (slot[n] = its place k in the dynamic set).
void AddMeansGradientKernel(int count, const int* slot, const double* d_means,
                            const double* d_x0, double* out);

// to[i] += from[i], i < count.
void AddDoublesKernel(long long count, const double* from, double* to);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_
