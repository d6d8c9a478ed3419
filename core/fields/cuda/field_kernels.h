#ifndef EULERSPLAT_CORE_FIELDS_CUDA_FIELD_KERNELS_H_
#define EULERSPLAT_CORE_FIELDS_CUDA_FIELD_KERNELS_H_

// The fields' kernels (triplane.cu, mlp.cu), as the device fields launch
// them. Plain types only; all arrays are device arrays of doubles, in the
// CPU fields' layouts. Computation is in double: the parameters are Ceres'
// double blocks, the Euler chain compounds each step's error over a whole
// cycle forward and backward, and the CPU twins are double, so the device
// matches them to rounding; the fields' products are small (widths of
// 16..128) and bound by memory and latency more than by FP64 throughput.

namespace es {
namespace cuda {

// A Triplane's sampling constants (core/fields/triplane.h).
struct TriplaneGeometry {
  int resolution = 0;
  int channels = 0;
  int combination = 0;  // static_cast<int>(PlaneCombination)
  double lo[3] = {0, 0, 0};
  double texels_per_unit[3] = {0, 0, 0};  // (R - 1) / (hi - lo)
};

// Triplane::Sample of n points: out rows out_stride apart.
void TriplaneSampleKernel(const TriplaneGeometry& g, const double* params,
                          int n, const double* x, double* out,
                          int out_stride);
// Triplane::Backward: accumulates into d_params (atomically: points share
// texels) and d_x (n x 3); either may be null.
void TriplaneBackwardKernel(const TriplaneGeometry& g, const double* params,
                            int n, const double* x, const double* d_out,
                            int d_out_stride, double* d_params, double* d_x);

// Triplane::TotalVariation's terms (total_variation.cu), one thread per
// parameter of a resolution x resolution x channels triplane: partials[b]
// = block b's sum of the squared differences to the right and lower
// neighbours, and with d_params set, d_params += grad_scale times that
// sum's derivative. Blocks: TotalVariationBlocks(3 R R C).
int TotalVariationBlocks(long long num_params);
void TotalVariationKernel(int resolution, int channels, const double* params,
                          double grad_scale, double* d_params,
                          double* partials);
// sum[0]: the partials of `blocks` blocks, added in block order.
void SumTotalVariationPartials(int blocks, const double* partials,
                               double* sum);

// One dense layer, rows x in -> rows x out, W out x in row-major, bias b:
// y = a W^T + b, then max(y, 0) as std::max keeps NaN when relu.
void LayerForwardKernel(int rows, int in, int out, const double* a,
                        const double* w, const double* b, bool relu,
                        double* y);
// d (rows x in) = g W, or += g W when accumulate; with relu_input set
// (rows x in, the layer's input), 0 where relu_input <= 0 or is NaN.
void LayerInputGradientKernel(int rows, int out, int in, const double* g,
                              const double* w, const double* relu_input,
                              bool accumulate, double* d);
// dw (out x in) += g^T a and db (out) += the column sums of g.
void LayerWeightGradientKernel(int rows, int in, int out, const double* g,
                               const double* a, double* dw, double* db);

// out[i] = in[i] * scales[i % dim] for i < count (in may be out).
void ScaleColumnsKernel(long long count, int dim, const double* scales,
                        const double* in, double* out);

// EncodeSinusoidal of t[i] and then p[i] into columns [column,
// column + 2 (t_frequencies + p_frequencies)) of rows stride apart.
void EncodeCycleKernel(int n, const int* t, const int* p, int t_frequencies,
                       double t_period, int p_frequencies, double p_period,
                       double* rows, int stride, int column);

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_CUDA_FIELD_KERNELS_H_
