#ifndef EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_
#define EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_

// The frame composition kernel (compose.cu), as DeviceLoopRenderer
// launches it. Plain types only; all pointers are device pointers.

namespace es {
namespace cuda {

// Where D's outputs sit in one of its rows (core/fields/residual_field.h).
struct ResidualLayout {
  int dim = 0, position = 0, opacity = 0, sh = 0;
};

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

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_CUDA_COMPOSE_KERNELS_H_
