#ifndef EULERSPLAT_COSTS_CUDA_DEVICE_WATER_ENERGY_LOSS_H_
#define EULERSPLAT_COSTS_CUDA_DEVICE_WATER_ENERGY_LOSS_H_

// WaterEnergyLoss (costs/water_energy_loss.h) on a CUDA device: the motion
// and detail energies of two consecutive rendered frames against the
// input frames, per opponent channel, with the same blurs, bands, masks
// and eps, computed in double as the CPU does (an amplitude is a square
// root of a blurred square: float would lose the small energies the loss
// compares). No CUDA types; failures throw CudaError.

#include <vector>

#include "core/base/cuda/device_buffer.h"
#include "costs/cuda/water_energy_kernels.h"
#include "costs/water_energy_terms.h"

namespace es {
namespace cuda {

// Keeps its scratch between calls: not thread-safe.
class DeviceWaterEnergyLoss {
 public:
  explicit DeviceWaterEnergyLoss(const WaterEnergyOptions& options);

  const WaterEnergyOptions& options() const { return options_; }

  // All pointers are device arrays. rendered_a / rendered_b, input_a /
  // input_b: H x W x 3 floats, RGB (DeviceImages::rgb's layout; frame B is
  // A's next); mask_a / mask_b: both null (every pixel is water) or H x W
  // floats in [0, 1] (> 0.5 = water). Returns (motion_weight motion +
  // detail_weight detail) scale; d_a / d_b (nullable, H x W x 3) receive
  // += scale d loss / d rendered; `terms` (nullable) the unweighted terms.
  // Only the loss's sums come back to the host.
  double Evaluate(const float* rendered_a, const float* rendered_b,
                  const float* input_a, const float* input_b,
                  const float* mask_a, const float* mask_b, int width,
                  int height, double scale, float* d_a, float* d_b,
                  WaterEnergyTerms* terms = nullptr);

 private:
  // G_k's and W_k's taps in taps_: offset and radius.
  struct Taps {
    const double* taps;
    int radius;
  };
  Taps Detail(int k) const;
  Taps Window(int k) const;
  // The rendered energies' floors of a term (band k; -1: motion).
  ChannelFloors Floors(int band) const;

  WaterEnergyOptions options_;
  std::vector<size_t> detail_offset_, window_offset_;
  std::vector<int> detail_radius_, window_radius_;
  WaterEnergyKernels kernels_;
  DeviceBuffer<double> taps_;
  // Per-pixel planes (see Evaluate) and the sums' partials.
  DeviceBuffer<double> water_, y_, dy_, diff_, square_, energy_, d_e_, g_,
      high_, low_, coarse_, scratch_, partials_, sums_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_COSTS_CUDA_DEVICE_WATER_ENERGY_LOSS_H_
