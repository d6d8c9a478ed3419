#include "costs/cuda/device_residual_l2_loss.h"

#include <glog/logging.h>

#include "costs/cuda/mean_loss_kernels.h"

namespace es {
namespace cuda {

double DeviceResidualL2Loss::Evaluate(const double* residuals,
                                      long long count, double scale,
                                      double* d_residuals) {
  CHECK_GE(count, 0);
  if (count == 0) return 0.0;
  // ResidualL2Mean's inv and 2 scale inv, in the same order.
  const double inv = 1.0 / static_cast<double>(count);
  const int blocks = MeanLossBlocks(count);
  partials_.Resize(blocks);
  sum_.Resize(1);
  ResidualL2Terms(count, residuals, 2.0 * scale * inv, d_residuals,
                  partials_.data());
  SumMeanLossPartials(blocks, partials_.data(), sum_.data());
  double sum;
  sum_.Download(&sum);
  return sum * inv;
}

}  // namespace cuda
}  // namespace es
