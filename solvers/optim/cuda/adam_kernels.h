#ifndef EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_
#define EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_

// Device Adam's kernel (adam.cu): plain types only, device pointers.

#include "solvers/optim/adam_value.h"

namespace es {
namespace cuda {

// AdamStep's constants of one step and rate; `on` false: leave the values.
struct AdamKernelStep {
  AdamConstants constants;
  bool on = false;
};

// AdamStep::Update of values [0, n): value i with (i % period) < head
// takes `head_step`, the others `tail_step` (one block: period 1, head 1;
// SH: period 3K, head 3, the DC and the higher bands).
void AdamUpdateKernel(long long n, int period, int head,
                      const AdamKernelStep& head_step,
                      const AdamKernelStep& tail_step, const double* grad,
                      double* m, double* v, double* x);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_CUDA_ADAM_KERNELS_H_
