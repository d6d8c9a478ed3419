#ifndef EULERSPLAT_CORE_LOOP_LOOP_FRAMES_FACTORY_H_
#define EULERSPLAT_CORE_LOOP_LOOP_FRAMES_FACTORY_H_

#include <functional>
#include <memory>

#include "core/loop/loop_frames.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"

namespace es {

// Makes the frames of a model (which must outlive them) on some device:
// the stages that play a loop (es_animate's, es_eval's) take one, and
// apps/common/loop_frames_on.h picks it by --device.
using LoopFramesFactory = std::function<std::unique_ptr<LoopFrames>(
    const LoopModel* model, const RenderOptions& options)>;

inline std::unique_ptr<LoopFrames> MakeCpuLoopFrames(
    const LoopModel* model, const RenderOptions& options) {
  return std::make_unique<CpuLoopFrames>(model, options);
}

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_FRAMES_FACTORY_H_
