#ifndef EULERSPLAT_SOLVERS_OPTIM_CUDA_DEVICE_ADAM_H_
#define EULERSPLAT_SOLVERS_OPTIM_CUDA_DEVICE_ADAM_H_

// Adam (solvers/optim/adam.h) on double parameters in device memory: the
// same bias correction, epsilon and update order, value by value, as
// AdamStep::Update. No CUDA types; failures throw CudaError.

#include <array>
#include <cstdint>

#include "core/base/cuda/device_buffer.h"
#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"

namespace es {
namespace cuda {

// AdamUpdate on device arrays of n values (gradient, moments, parameters).
// Skips nothing: the CPU's skip of all-zero chunks leaves them as this
// update does.
void DeviceAdamUpdate(const AdamOptions& options, int64_t t, double lr,
                      int n, const double* grad, double* m, double* v,
                      double* x);

// Device arrays of a GaussianSet's arrays, in kGaussianArrays order and
// their layouts.
struct DeviceGaussianBlocks {
  int count = 0;
  int sh_degree = 0;
  std::array<double*, kNumGaussianArrays> arrays{};
};

// GaussianAdam::Step on the device: each block with a non-zero learning
// rate, the SH block with its DC and higher-band rates. Owns the moments
// (zeros after Reset).
class DeviceGaussianAdam {
 public:
  explicit DeviceGaussianAdam(const AdamOptions& options = {})
      : options_(options) {}

  void Reset(int count, int sh_degree);
  // grad: the same shapes as params (only read).
  void Step(const GaussianLearningRates& lr, const DeviceGaussianBlocks& grad,
            const DeviceGaussianBlocks& params);

  int64_t step() const { return step_; }
  // The moments, as GaussianAdam's m() and v() hold them.
  void Download(GaussianSet* m, GaussianSet* v) const;
  // GaussianAdam's state() and Restore(): moments and step counter to and
  // from the host (checkpoints, and edits done on the host such as
  // densification).
  GaussianAdamState State() const;
  void Restore(const GaussianAdamState& state);

 private:
  using Moments = std::array<DeviceBuffer<double>, kNumGaussianArrays>;
  AdamOptions options_;
  int64_t step_ = 0;
  int count_ = 0, sh_degree_ = 0;
  Moments m_, v_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_CUDA_DEVICE_ADAM_H_
