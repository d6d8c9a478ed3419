#include "core/render/render_maps.h"

#include <glog/logging.h>

namespace es {
namespace {

// values[i * stride + offset] / alpha[i] where alpha[i] > min_alpha.
std::vector<double> AlphaNormalized(const RenderResult& result,
                                    const std::vector<double>& values,
                                    int stride, int offset, double min_alpha) {
  const size_t pixels = result.alpha.size();
  CHECK_EQ(values.size(), pixels * stride);
  std::vector<double> out(pixels, 0.0);
  for (size_t i = 0; i < pixels; ++i) {
    const double a = result.alpha[i];
    if (a > min_alpha) out[i] = values[i * stride + offset] / a;
  }
  return out;
}

}  // namespace

std::vector<double> ExpectedDepth(const RenderResult& result,
                                  double min_alpha) {
  return AlphaNormalized(result, result.depth, 1, 0, min_alpha);
}

std::vector<double> NormalizedExtra(const RenderResult& result, int channel,
                                    double min_alpha) {
  const size_t pixels = result.alpha.size();
  CHECK_GT(pixels, 0u);
  const int num_extra = static_cast<int>(result.extra.size() / pixels);
  CHECK_GE(channel, 0);
  CHECK_LT(channel, num_extra);
  return AlphaNormalized(result, result.extra, num_extra, channel, min_alpha);
}

}  // namespace es
