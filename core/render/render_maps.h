#ifndef EULERSPLAT_CORE_RENDER_RENDER_MAPS_H_
#define EULERSPLAT_CORE_RENDER_RENDER_MAPS_H_

#include <vector>

#include "core/render/rasterizer.h"

namespace es {

// Per-pixel maps derived from a render (H*W, row-major). The rasterizer
// composites values weighted by w_i, so dividing by alpha = sum_i w_i gives
// the average over the visible surface; pixels with alpha <= min_alpha (no
// surface) are 0.

// Expected camera-z depth of the visible surface.
std::vector<double> ExpectedDepth(const RenderResult& result,
                                  double min_alpha = 1e-3);

// Average of extra channel `channel` (e.g. the dynamic probability).
std::vector<double> NormalizedExtra(const RenderResult& result, int channel,
                                    double min_alpha = 1e-3);

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_RENDER_MAPS_H_
