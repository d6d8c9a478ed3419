#ifndef EULERSPLAT_COSTS_CUDA_SPLAT_COST_KERNELS_H_
#define EULERSPLAT_COSTS_CUDA_SPLAT_COST_KERNELS_H_

// The element-wise steps of the device render costs (DeviceSplatRenderCost,
// DeviceJointRenderCost, DeviceJointObjective; splat_cost.cu) around the
// rasterizer and the losses: plain types only, device pointers, one thread per value, double
// as the CPU's costs compute them (images in float, as rendered).

namespace es {
namespace cuda {

// probability[i] = Sigmoid(logits[i]) (core/model/gaussians.h), i < n.
void SigmoidArray(int n, const double* logits, double* probability);

// out[i] = d_probability[i] * p (1 - p) * scale with p = probability[i]:
// RenderedFrameLoss::DynamicLogitGradient.
void DynamicLogitGradient(int n, const double* d_probability,
                          const double* probability, double scale,
                          double* out);
// The same added (+=) into out, for callers that accumulate gradients.
void AddDynamicLogitGradient(int n, const double* d_probability,
                             const double* probability, double scale,
                             double* out);

// x[i] *= scale, i < n.
void ScaleArray(long long n, double scale, double* x);

// to[i] += from[i], i < n (float images, e.g. image gradients).
void AddFloatArray(long long n, const float* from, float* to);

// a[i] = 0.5 (a[i] + b[i]) for i < n: the mean of two gradients.
void AverageInto(long long n, const double* b, double* a);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_SPLAT_COST_KERNELS_H_
