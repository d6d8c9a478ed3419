#ifndef EULERSPLAT_CORE_LOOP_LOOP_FRAMES_H_
#define EULERSPLAT_CORE_LOOP_LOOP_FRAMES_H_

// The frames of a looping model as the binaries write them (es_animate):
// Alg. 2 played on the CPU (CpuLoopFrames, LoopRenderer) or on a GPU
// (cuda::DeviceLoopFrames), each frame's RGB image on the host.

#include <vector>

#include "core/loop/loop_renderer.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"

namespace es {

class LoopFrames {
 public:
  virtual ~LoopFrames() = default;

  virtual void Start(int frame) = 0;
  virtual void Advance() = 0;
  // The current frame seen from `camera`: H*W*3 RGB, background included;
  // valid until the next call.
  virtual const std::vector<double>& Rgb(const Camera& camera) = 0;
  // The CPU renderer behind the frames, whose positions and cycle indices
  // es_animate --tracks draws; nullptr on a GPU, where they stay there.
  virtual const LoopRenderer* cpu_renderer() const = 0;
};

class CpuLoopFrames : public LoopFrames {
 public:
  // The model must outlive the frames.
  CpuLoopFrames(const LoopModel* model, const RenderOptions& options)
      : renderer_(model, options) {}

  void Start(int frame) override { renderer_.Start(frame); }
  void Advance() override { renderer_.Advance(); }
  const std::vector<double>& Rgb(const Camera& camera) override {
    return renderer_.Render(camera).rgb;
  }
  const LoopRenderer* cpu_renderer() const override { return &renderer_; }

 private:
  LoopRenderer renderer_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_FRAMES_H_
