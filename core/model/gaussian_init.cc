#include "core/model/gaussian_init.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace es {
namespace {

// 3DGS clamps the squared distance at this so coincident points keep a
// finite log-scale.
constexpr double kMinSquaredDistance = 1e-7;
constexpr double kInitialOpacity = 0.1;

// Points bucketed in a uniform grid; cells are keyed by packed coordinates.
class PointGrid {
 public:
  explicit PointGrid(const std::vector<Eigen::Vector3d>& points)
      : points_(points) {
    lo_ = points[0];
    Eigen::Vector3d hi = points[0];
    for (const auto& p : points) {
      lo_ = lo_.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double extent = std::max((hi - lo_).maxCoeff(), 1e-12);
    cell_ =
        extent / std::max(1.0, std::cbrt(static_cast<double>(points.size())));
    for (int i = 0; i < 3; ++i)
      dims_[i] = static_cast<int>((hi[i] - lo_[i]) / cell_) + 1;
    std::vector<std::pair<int64_t, int>> keyed(points.size());
    for (size_t i = 0; i < points.size(); ++i)
      keyed[i] = {Key(CellOf(points[i])), static_cast<int>(i)};
    std::sort(keyed.begin(), keyed.end());
    order_.resize(keyed.size());
    for (size_t i = 0; i < keyed.size(); ++i) {
      order_[i] = keyed[i].second;
      auto& range = cells_[keyed[i].first];
      if (i == 0 || keyed[i - 1].first != keyed[i].first)
        range.first = static_cast<int>(i);
      range.second = static_cast<int>(i) + 1;
    }
  }

  // Squared distances to the k nearest points other than `self`, ascending.
  std::vector<double> Nearest(int self, int k) const {
    const Eigen::Vector3d& q = points_[self];
    const Eigen::Vector3i c = CellOf(q);
    std::vector<double> best;  // ascending, at most k
    const int max_ring = std::max({dims_[0], dims_[1], dims_[2]});
    for (int r = 0; r <= max_ring; ++r) {
      for (int dx = -r; dx <= r; ++dx)
        for (int dy = -r; dy <= r; ++dy)
          for (int dz = -r; dz <= r; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r)
              continue;
            const Eigen::Vector3i cc = c + Eigen::Vector3i(dx, dy, dz);
            if ((cc.array() < 0).any() || cc[0] >= dims_[0] ||
                cc[1] >= dims_[1] || cc[2] >= dims_[2])
              continue;
            const auto it = cells_.find(Key(cc));
            if (it == cells_.end()) continue;
            for (int j = it->second.first; j < it->second.second; ++j) {
              const int idx = order_[j];
              if (idx == self) continue;
              const double d2 = (points_[idx] - q).squaredNorm();
              if (static_cast<int>(best.size()) == k && d2 >= best.back())
                continue;
              best.insert(std::upper_bound(best.begin(), best.end(), d2), d2);
              if (static_cast<int>(best.size()) > k) best.pop_back();
            }
          }
      // Cells beyond ring r are at least r cells away from q.
      const double reach = r * cell_;
      if (static_cast<int>(best.size()) == k && best.back() <= reach * reach)
        break;
    }
    return best;
  }

 private:
  Eigen::Vector3i CellOf(const Eigen::Vector3d& p) const {
    Eigen::Vector3i c;
    for (int i = 0; i < 3; ++i)
      c[i] = std::min(dims_[i] - 1, static_cast<int>((p[i] - lo_[i]) / cell_));
    return c;
  }
  int64_t Key(const Eigen::Vector3i& c) const {
    return (static_cast<int64_t>(c[0]) * dims_[1] + c[1]) * dims_[2] + c[2];
  }

  const std::vector<Eigen::Vector3d>& points_;
  Eigen::Vector3d lo_;
  double cell_ = 1;
  int dims_[3] = {1, 1, 1};
  std::vector<int> order_;
  std::unordered_map<int64_t, std::pair<int, int>> cells_;
};

}  // namespace

std::vector<double> MeanSquaredKnnDistances(
    const std::vector<Eigen::Vector3d>& points, int k) {
  CHECK_GT(k, 0);
  std::vector<double> out(points.size(), 0.0);
  if (points.size() < 2) return out;
  const PointGrid grid(points);
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const std::vector<double> d2 = grid.Nearest(i, k);
    double sum = 0;
    for (double d : d2) sum += d;
    out[i] = sum / d2.size();
  }
  return out;
}

GaussianSet InitGaussiansFromPoints(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<Eigen::Vector3d>& colors,
                                    int sh_degree) {
  CHECK_EQ(points.size(), colors.size());
  GaussianSet g;
  g.sh_degree = sh_degree;
  g.Resize(static_cast<int>(points.size()));
  const std::vector<double> d2 = MeanSquaredKnnDistances(points, 3);
  const int k = g.sh_coeffs();
  for (int i = 0; i < g.size(); ++i) {
    const double log_scale =
        0.5 * std::log(std::max(d2[i], kMinSquaredDistance));
    for (int a = 0; a < 3; ++a) {
      g.means[3 * i + a] = points[i][a];
      g.log_scales[3 * i + a] = log_scale;
      g.sh[i * k * 3 + a] = (colors[i][a] - 0.5) / kShC0;
    }
    g.opacity_logits[i] = Logit(kInitialOpacity);
  }
  return g;
}

}  // namespace es
