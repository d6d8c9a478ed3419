#include "core/fields/cuda/device_triplane.h"

namespace es {
namespace cuda {

DeviceTriplane::DeviceTriplane(const Triplane& triplane)
    : output_dim_(triplane.output_dim()),
      num_params_(triplane.num_params()) {
  const TriplaneOptions& o = triplane.options();
  geometry_.resolution = o.resolution;
  geometry_.channels = o.channels;
  geometry_.combination = static_cast<int>(o.combination);
  for (int a = 0; a < 3; ++a) {
    const double lo = triplane.box_min()[a], hi = triplane.box_max()[a];
    geometry_.lo[a] = lo;
    // Triplane::SetBox's expression, so texel positions agree bit for bit.
    geometry_.texels_per_unit[a] = (o.resolution - 1.0) * (1.0 / (hi - lo));
  }
}

void DeviceTriplane::Sample(const double* params, int n, const double* x,
                            double* out, int out_stride) const {
  TriplaneSampleKernel(geometry_, params, n, x, out,
                       out_stride > 0 ? out_stride : output_dim_);
}

void DeviceTriplane::Backward(const double* params, int n, const double* x,
                              const double* d_out, double* d_params,
                              double* d_x, int d_out_stride) const {
  TriplaneBackwardKernel(geometry_, params, n, x, d_out,
                         d_out_stride > 0 ? d_out_stride : output_dim_,
                         d_params, d_x);
}

double DeviceTriplane::TotalVariation(const double* params, double weight,
                                      double* d_params,
                                      DeviceBuffer<double>* scratch) const {
  const int r = geometry_.resolution, c = geometry_.channels;
  // Triplane::TotalVariation's normalization: the number of pairs.
  const double scale = weight / (3.0 * c * 2.0 * r * (r - 1));
  const int blocks = TotalVariationBlocks(num_params_);
  scratch->Resize(blocks + 1);
  double* sum = scratch->data() + blocks;
  TotalVariationKernel(r, c, params, scale, d_params, scratch->data());
  SumTotalVariationPartials(blocks, scratch->data(), sum);
  double value;
  CopyToHost(&value, sum, sizeof(double));
  return scale * value;
}

}  // namespace cuda
}  // namespace es
