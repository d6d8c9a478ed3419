#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_TRAINING_KERNELS_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_TRAINING_KERNELS_H_

// The device trainer's own kernels (training.cu): plain types only, device
// pointers, one thread per value.

namespace es {
namespace cuda {

// DensityStats::AddView (solvers/train/densify.h) on device arrays of
// `count` Gaussians: where radii[i] > 0, grad_sum[i] += |(g_x half_w,
// g_y half_h)| of mean2d_grads[2i, 2i+1], views[i] += 1, max_radius[i] =
// max(max_radius[i], radii[i]).
void AddViewStats(int count, double half_w, double half_h, const int* radii,
                  const double* mean2d_grads, double* grad_sum,
                  double* views, double* max_radius);

// Sets *flag (device) to 1 if any of x[0, n) is NaN or infinite; leaves
// it otherwise.
void FlagNonFinite(long long n, const double* x, int* flag);

// Raises *max_bits (device) to the bits of the largest |x[i]|, i < n, if
// those are larger: the bits of non-negative doubles order as the values
// do, with NaN above infinity, so a block's largest magnitude (and whether
// it is finite) comes back as one integer. Zero *max_bits first;
// MagnitudeOfBits reads it.
void RaiseMaxMagnitudeBits(long long n, const double* x,
                           unsigned long long* max_bits);
// The magnitude RaiseMaxMagnitudeBits left, +infinity for NaN (as
// MaxMagnitude, solvers/train/divergence_guard.h).
double MagnitudeOfBits(unsigned long long bits);

// ClampScales (solvers/train/water_particles.h): for the m Gaussians
// dynamic[k], each of their three log-scales at most max_log_scale[k].
void ClampLogScales(int m, const int* dynamic, const double* max_log_scale,
                    double* log_scales);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_TRAINING_KERNELS_H_
