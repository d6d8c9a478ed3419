#ifndef EULERSPLAT_APPS_COMMON_LOOP_FRAMES_ON_H_
#define EULERSPLAT_APPS_COMMON_LOOP_FRAMES_ON_H_

// The frames of a looping model on the device --device chose
// (apps/common/device_flag.h): CpuLoopFrames or cuda::DeviceLoopFrames.

#include <memory>

#include "apps/common/device_flag.h"
#include "core/loop/loop_frames_factory.h"

namespace es {

// The model must outlive the frames.
std::unique_ptr<LoopFrames> LoopFramesOn(ComputeDevice device,
                                         const LoopModel* model,
                                         const RenderOptions& options);
// The same as a factory, for the stages that make their own.
LoopFramesFactory LoopFramesOn(ComputeDevice device);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_LOOP_FRAMES_ON_H_
