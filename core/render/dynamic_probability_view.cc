#include "core/render/dynamic_probability_view.h"

namespace es {

SplatView DynamicProbabilityView(const GaussianSet& g,
                                 std::vector<double>* probability) {
  probability->resize(g.size());
  for (int i = 0; i < g.size(); ++i)
    (*probability)[i] = Sigmoid(g.dynamic_logits[i]);
  SplatView view = SplatView::Of(g);
  view.num_extra = 1;
  view.extra = probability->data();
  return view;
}

}  // namespace es
