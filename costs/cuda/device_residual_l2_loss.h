#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_RESIDUAL_L2_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_RESIDUAL_L2_LOSS_H_

// ResidualL2Loss (costs/residual_l2_cost.h) on a CUDA device: the mean of
// the squares of D's outputs (num_dynamic x kResidualDim doubles,
// row-major, as the CPU field writes them). No CUDA types; failures throw
// CudaError.

#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DeviceResidualL2Loss {
 public:
  // The loss of `count` device doubles (0 when count is 0, with nothing
  // launched); if d_residuals (device, count doubles) is not null it
  // receives scale * dl / d residuals. Only the loss's sum comes back to
  // the host.
  double Evaluate(const double* residuals, long long count, double scale,
                  double* d_residuals);

 private:
  DeviceBuffer<double> partials_, sum_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_RESIDUAL_L2_LOSS_H_
