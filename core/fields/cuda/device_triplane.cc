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

}  // namespace cuda
}  // namespace es
