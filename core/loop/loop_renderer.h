#ifndef EULERSPLAT_CORE_LOOP_LOOP_RENDERER_H_
#define EULERSPLAT_CORE_LOOP_LOOP_RENDERER_H_

#include <optional>
#include <vector>

#include "core/loop/euler_chain.h"
#include "core/loop/frame_composer.h"
#include "core/loop/loop_animator.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"

namespace es {

// Plays a trained looping model as an animation: Alg. 2 moves the dynamic
// Gaussians (Start once, O(N L); then one Euler step per frame, O(N)), the
// residual field is applied with cycle number p = 0, so frame k and frame
// k + L are identical, and any camera renders the current frame. A model
// without a motion field keeps its dynamic Gaussians at their canonical
// positions (only D animates them).
class LoopRenderer {
 public:
  // The model must outlive the renderer.
  LoopRenderer(const LoopModel* model, const RenderOptions& options,
               const EulerOptions& euler_options = {});

  void Start(int frame);
  void Advance();
  int frame() const { return frame_; }

  // The splats of the current frame, every offset applied (what Render
  // draws); valid until the next Compose or Render.
  const SplatView& Compose();
  // Renders the current frame; the result stays valid until the next call.
  const RenderResult& Render(const Camera& camera);

  // The current dynamic positions (num_dynamic x 3, in dynamic order) and
  // cycle indices.
  const std::vector<double>& positions() const;
  const std::vector<int>& cycle_indices() const;
  // Euler-step counts since Start.
  EulerStats euler_stats() const;

 private:
  const LoopModel* model_;
  RenderOptions options_;
  LoopModelView view_;
  std::optional<LoopAnimator> animator_;  // absent without a motion field
  std::vector<double> canonical_;         // dynamic x0, num_dynamic x 3
  std::vector<int> cycle_index_;          // used without a motion field
  int frame_ = 0;
  bool started_ = false;
  FrameComposer composer_;
  Rasterizer rasterizer_;
  RenderResult result_;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_RENDERER_H_
