#ifndef EULERSPLAT_COSTS_CUDA_MEAN_LOSS_KERNELS_H_
#define EULERSPLAT_COSTS_CUDA_MEAN_LOSS_KERNELS_H_

// The kernels of the device losses that are means of per-value terms
// (mean_losses.cu): the mask BCE and the residual L2, as
// DeviceMaskBceLoss and DeviceResidualL2Loss launch them. Plain types
// only; all pointers are device pointers.

namespace es {
namespace cuda {

// Blocks of the value-parallel passes, each writing one partial sum.
int MeanLossBlocks(long long n);

// Per pixel i < n the BCE of p = extra[i num_extra + channel] (clamped as
// MaskBceMean does) against mask[i]; with d_extra set, d_extra at the same
// place = grad_scale ((1 - t) / (1 - p) - t / p), 0 where the clamp is
// active. partials[b]: block b's sum of the BCE terms.
void MaskBceTerms(long long n, const float* extra, int num_extra,
                  int channel, const float* mask, double grad_scale,
                  float* d_extra, double* partials);
// partials[b]: block b's sum of r^2; with d set, d = grad_scale r.
void ResidualL2Terms(long long n, const double* residuals, double grad_scale,
                     double* d, double* partials);
// sum[0]: the partial sums of `blocks` blocks, in block order.
void SumMeanLossPartials(int blocks, const double* partials, double* sum);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_MEAN_LOSS_KERNELS_H_
