#ifndef EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_DENSITY_STATS_H_
#define EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_DENSITY_STATS_H_

// DensityStats (solvers/train/densify.h) accumulated on the device from
// the device rasterizer's last render, moved to the host only for a
// densification step or a checkpoint. No CUDA types.

#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/device_rasterizer.h"
#include "solvers/train/densify.h"

namespace es {
namespace cuda {

class DeviceDensityStats {
 public:
  // `count` Gaussians, every statistic zero.
  void Reset(int count);
  // DensityStats::AddView of the rasterizer's last forward and backward
  // (its RadiiDevice and Mean2dGradientsDevice) on a width x height view.
  void AddView(int width, int height, const DeviceRasterizer& rasterizer);

  void Upload(const DensityStats& stats);
  void Download(DensityStats* stats) const;
  int size() const { return count_; }

 private:
  int count_ = 0;
  DeviceBuffer<double> grad_sum_, views_, max_radius_;
  DeviceBuffer<int> radii_;
  DeviceBuffer<double> mean2d_grads_;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_CUDA_DEVICE_DENSITY_STATS_H_
