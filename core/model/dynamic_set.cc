#include "core/model/dynamic_set.h"

#include <limits>

namespace es {
namespace {

// Fraction of the dynamic Gaussians' extent added around them, so the
// fields still see their neighbourhood as positions move.
constexpr double kBoxPadding = 0.1;
// Smallest box half-size, for a single (or no) dynamic Gaussian.
constexpr double kMinBoxMargin = 1e-3;

}  // namespace

std::vector<int> DynamicSet(const GaussianSet& g, double threshold) {
  return DynamicSet(g.dynamic_logits, threshold);
}

std::vector<int> DynamicSet(const std::vector<double>& dynamic_logits,
                            double threshold) {
  std::vector<int> out;
  for (size_t i = 0; i < dynamic_logits.size(); ++i)
    if (Sigmoid(dynamic_logits[i]) > threshold)
      out.push_back(static_cast<int>(i));
  return out;
}

void FieldBox(const GaussianSet& g, const std::vector<int>& indices,
              Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  lo->setConstant(std::numeric_limits<double>::infinity());
  hi->setConstant(-std::numeric_limits<double>::infinity());
  auto add = [&](int i) {
    const Eigen::Vector3d x(&g.means[3 * i]);
    if (!x.allFinite()) return;
    *lo = lo->cwiseMin(x);
    *hi = hi->cwiseMax(x);
  };
  if (indices.empty()) {
    for (int i = 0; i < g.size(); ++i) add(i);
  } else {
    for (int i : indices) add(i);
  }
  if (!lo->allFinite()) {
    lo->setConstant(-1.0);
    hi->setConstant(1.0);
    return;
  }
  const Eigen::Vector3d pad =
      (kBoxPadding * (*hi - *lo)).cwiseMax(kMinBoxMargin);
  *lo -= pad;
  *hi += pad;
}

}  // namespace es
