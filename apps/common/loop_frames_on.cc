#include "apps/common/loop_frames_on.h"

#ifdef ES_HAVE_CUDA
#include "core/loop/cuda/device_loop_frames.h"
#endif

namespace es {

std::unique_ptr<LoopFrames> LoopFramesOn(ComputeDevice device,
                                         const LoopModel* model,
                                         const RenderOptions& options) {
#ifdef ES_HAVE_CUDA
  if (device == ComputeDevice::kCuda)
    return std::make_unique<cuda::DeviceLoopFrames>(model, options);
#else
  (void)device;  // ParseDeviceFlag refuses cuda in such a build
#endif
  return MakeCpuLoopFrames(model, options);
}

LoopFramesFactory LoopFramesOn(ComputeDevice device) {
  return [device](const LoopModel* model, const RenderOptions& options) {
    return LoopFramesOn(device, model, options);
  };
}

}  // namespace es
