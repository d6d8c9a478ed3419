#include "solvers/train/cuda/device_density_stats.h"

#include <glog/logging.h>

#include "solvers/train/cuda/training_kernels.h"

namespace es {
namespace cuda {

void DeviceDensityStats::Reset(int count) {
  count_ = count;
  for (DeviceBuffer<double>* b : {&grad_sum_, &views_, &max_radius_}) {
    b->Resize(count);
    b->Zero();
  }
}

void DeviceDensityStats::AddView(int width, int height,
                                 const DeviceRasterizer& rasterizer) {
  radii_.Resize(count_);
  mean2d_grads_.Resize(2 * static_cast<size_t>(count_));
  rasterizer.RadiiDevice(radii_.data());
  rasterizer.Mean2dGradientsDevice(mean2d_grads_.data());
  AddViewStats(count_, 0.5 * width, 0.5 * height, radii_.data(),
               mean2d_grads_.data(), grad_sum_.data(), views_.data(),
               max_radius_.data());
}

void DeviceDensityStats::Upload(const DensityStats& stats) {
  CHECK_EQ(stats.count.size(), stats.grad_sum.size());
  CHECK_EQ(stats.max_radius.size(), stats.grad_sum.size());
  count_ = stats.size();
  grad_sum_.Upload(stats.grad_sum);
  views_.Upload(stats.count);
  max_radius_.Upload(stats.max_radius);
}

void DeviceDensityStats::Download(DensityStats* stats) const {
  stats->grad_sum = grad_sum_.Download();
  stats->count = views_.Download();
  stats->max_radius = max_radius_.Download();
}

}  // namespace cuda
}  // namespace es
