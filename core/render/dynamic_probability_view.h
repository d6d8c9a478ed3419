#ifndef EULERSPLAT_CORE_RENDER_DYNAMIC_PROBABILITY_VIEW_H_
#define EULERSPLAT_CORE_RENDER_DYNAMIC_PROBABILITY_VIEW_H_

#include <vector>

#include "core/model/gaussians.h"
#include "core/render/splat_view.h"

namespace es {

// All of g with one extra channel, each Gaussian's dynamic (water)
// probability sigmoid(dynamic_logit), kept in *probability (which must
// outlive the view): its render's extra channel is the water the model
// sees, NormalizedExtra(render, 0) per pixel.
SplatView DynamicProbabilityView(const GaussianSet& g,
                                 std::vector<double>* probability);

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_DYNAMIC_PROBABILITY_VIEW_H_
