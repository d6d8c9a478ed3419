#include "core/loop/cuda/device_loop_frames.h"

#include <algorithm>

#include "core/base/cuda/device_buffer.h"

namespace es {
namespace cuda {

const std::vector<double>& DeviceLoopFrames::Rgb(const Camera& camera) {
  const DeviceImages& images = renderer_.Render(camera, background_);
  download_.resize(3 * static_cast<size_t>(images.width) * images.height);
  CopyToHost(download_.data(), images.rgb, download_.size() * sizeof(float));
  rgb_.resize(download_.size());
  std::copy(download_.begin(), download_.end(), rgb_.begin());
  return rgb_;
}

}  // namespace cuda
}  // namespace es
