#include "solvers/train/water_densify.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <glog/logging.h>

#include "core/loop/cycle_time.h"
#include "solvers/train/densify.h"

namespace es {
namespace {

// 3DGS: a split child is 1 / (0.8 * 2) the parent's size.
constexpr double kSplitShrink = 1.6;

}  // namespace

std::vector<int> PickWaterToDensify(const std::vector<int>& dynamic_index,
                                    const std::vector<double>& mean_grad,
                                    double fraction, int max_dynamic) {
  CHECK_EQ(dynamic_index.size(), mean_grad.size());
  const int n = static_cast<int>(dynamic_index.size());
  std::vector<int> order;
  for (int k = 0; k < n; ++k)
    if (mean_grad[k] > 0) order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return mean_grad[a] > mean_grad[b];
  });
  const int wanted = static_cast<int>(std::ceil(fraction * n));
  const int count = std::max(
      0, std::min({wanted, max_dynamic - n, static_cast<int>(order.size())}));
  std::vector<int> picked(count);
  for (int k = 0; k < count; ++k) picked[k] = dynamic_index[order[k]];
  return picked;
}

WaterDensifyResult DensifyWater(const std::vector<int>& picked,
                                const std::vector<double>& split_scale,
                                int child_cycle_length, std::mt19937_64* rng,
                                LoopModel* model, GaussianAdam* adam) {
  GaussianSet* g = &model->gaussians;
  std::vector<int>* dynamic_index = &model->dynamic_index;
  std::vector<int>* start_times = &model->start_times;
  CHECK_EQ(picked.size(), split_scale.size());
  CHECK_EQ(dynamic_index->size(), start_times->size());
  CHECK_GE(child_cycle_length, 0);
  std::unordered_map<int, int> start_of;
  for (size_t k = 0; k < dynamic_index->size(); ++k)
    start_of[(*dynamic_index)[k]] = (*start_times)[k];

  WaterDensifyResult result;
  GaussianSet added;
  added.sh_degree = g->sh_degree;
  std::vector<int> added_start;
  std::vector<bool> keep(g->size(), true);
  for (size_t k = 0; k < picked.size(); ++k) {
    const int i = picked[k];
    CHECK(start_of.count(i)) << "densifying a static Gaussian " << i;
    const bool split = MaxScale(*g, i) > split_scale[k];
    const int children = split ? 2 : 1;
    for (int c = 0; c < children; ++c) {
      std::normal_distribution<double> normal(0.0, 1.0);
      AppendSampledChild(*g, i, split ? kSplitShrink : 1.0, &normal, rng,
                         &added);
      added_start.push_back(child_cycle_length > 0
                                ? DrawStartTime(child_cycle_length, rng)
                                : start_of[i]);
    }
    if (split) {
      keep[i] = false;
      ++result.split;
    } else {
      ++result.cloned;
    }
  }

  // Kept Gaussians keep their order; children follow.
  std::vector<int> new_index(g->size(), -1);
  int kept = 0;
  for (int i = 0; i < g->size(); ++i)
    if (keep[i]) new_index[i] = kept++;
  std::vector<int> index, times;
  for (size_t k = 0; k < dynamic_index->size(); ++k) {
    const int i = (*dynamic_index)[k];
    if (!keep[i]) continue;
    index.push_back(new_index[i]);
    times.push_back((*start_times)[k]);
  }
  for (int j = 0; j < added.size(); ++j) {
    index.push_back(kept + j);
    times.push_back(added_start[j]);
  }
  g->Filter(keep);
  adam->Filter(keep);
  for (int j = 0; j < added.size(); ++j) g->AppendFrom(added, j);
  adam->AppendZeros(added.size());
  *dynamic_index = std::move(index);
  *start_times = std::move(times);
  return result;
}

}  // namespace es
