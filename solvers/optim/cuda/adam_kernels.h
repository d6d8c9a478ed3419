#ifndef EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_
#define EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_

// Device Adam's kernel (adam.cu): plain types only, device pointers.

namespace es {
namespace cuda {

// AdamStep's constants of one step and rate; `on` false: leave the values.
struct AdamConstants {
  double beta1 = 0, beta2 = 0, eps = 0, step = 0, inv_sqrt_bc2 = 0;
  bool on = false;
};

// AdamStep::Update of values [0, n): value i with (i % period) < head
// takes `head_step`, the others `tail_step` (one block: period 1, head 1;
// SH: period 3K, head 3, the DC and the higher bands).
void AdamUpdateKernel(long long n, int period, int head,
                      const AdamConstants& head_step,
                      const AdamConstants& tail_step, const double* grad,
                      double* m, double* v, double* x);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_
