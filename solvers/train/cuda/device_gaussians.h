#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_GAUSSIANS_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_GAUSSIANS_H_

// A GaussianSet's arrays (kGaussianArrays) in device memory (its layouts,
// double): the device trainer's parameters and gradients. No CUDA types.

#include <array>
#include <vector>

#include "core/model/gaussians.h"
#include "core/base/cuda/device_buffer.h"
#include "solvers/optim/cuda/device_adam.h"

namespace es {
namespace cuda {

class DeviceGaussians {
 public:
  void Upload(const GaussianSet& g);
  void Download(GaussianSet* g) const;
  // The dynamic logits alone (N doubles), for the dynamic set's refresh.
  std::vector<double> DownloadDynamicLogits() const {
    return arrays_[kDynamicArray].Download();
  }
  // `count` Gaussians of degree `sh_degree`, every value zero.
  void ResizeZero(int count, int sh_degree);

  int size() const { return count_; }
  int sh_degree() const { return sh_degree_; }
  DeviceGaussianBlocks Blocks();
  // The blocks in SplatBlock order (costs/splat_render_cost.h).
  std::vector<double*> BlockPointers();
  // Whether every value is finite: one int comes back to the host.
  bool AllFinite();
  // Sets *flag (device) non-zero where a value is not finite and leaves it
  // otherwise; nothing comes back, so a caller can check more arrays with
  // the same flag and download it once.
  void MarkNonFinite(int* flag);
  // MaxMagnitude of each array (kGaussianArrays order), +infinity for one
  // that is not finite: one integer per array comes back to the host.
  std::vector<double> MaxMagnitudes();
  // Raises bits[0, kNumGaussianArrays) (device) as RaiseMaxMagnitudeBits
  // does, one per array; nothing comes back.
  void RaiseMaxMagnitudes(unsigned long long* bits);

 private:
  int count_ = 0, sh_degree_ = 0;
  std::array<DeviceBuffer<double>, kNumGaussianArrays> arrays_;
  DeviceBuffer<int> flag_;
  DeviceBuffer<unsigned long long> magnitude_bits_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_GAUSSIANS_H_
