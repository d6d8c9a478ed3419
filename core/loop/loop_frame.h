#ifndef EULERSPLAT_CORE_LOOP_LOOP_FRAME_H_
#define EULERSPLAT_CORE_LOOP_LOOP_FRAME_H_

#include "core/model/gaussians.h"
#include "core/loop/loop_model.h"
#include "core/render/rasterizer.h"

namespace es {

// The splats of animation frame `frame` (>= 0) as es_animate plays it
// (Alg. 2 positions, D's position / opacity / SH offsets at cycle number
// p = 0), as a plain GaussianSet that any 3DGS tool can show: a state the
// loop really passes through, unlike the canonical splats. Frame k and
// k + L are identical. Dynamic logits are the canonical ones.
GaussianSet LoopFrameSplats(const LoopModel& model, int frame);

// Copies composed splats (a LoopRenderer's Compose) into a GaussianSet with
// the given model's dynamic logits.
GaussianSet CopySplats(const SplatView& view, const GaussianSet& canonical);

}  // namespace es

#endif  // EULERSPLAT_CORE_LOOP_LOOP_FRAME_H_
