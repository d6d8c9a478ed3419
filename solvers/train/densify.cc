#include "solvers/train/densify.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/base/stage_profile.h"

namespace es {
namespace {

// A split Gaussian becomes this many, each scaled down by 1 / (0.8 * count).
constexpr int kSplitCount = 2;

}  // namespace

double MaxScale(const GaussianSet& g, int i) {
  return std::exp(std::max(
      {g.log_scales[3 * i], g.log_scales[3 * i + 1], g.log_scales[3 * i + 2]}));
}

void AppendSampledChild(const GaussianSet& g, int i, double shrink,
                        std::normal_distribution<double>* normal,
                        std::mt19937_64* rng, GaussianSet* added) {
  added->AppendFrom(g, i);
  const int j = added->size() - 1;
  const Eigen::Quaterniond q(g.quats[4 * i], g.quats[4 * i + 1],
                             g.quats[4 * i + 2], g.quats[4 * i + 3]);
  Eigen::Vector3d offset;
  for (int a = 0; a < 3; ++a)
    offset[a] = (*normal)(*rng) * std::exp(g.log_scales[3 * i + a]);
  const Eigen::Vector3d mean = Eigen::Vector3d::Map(&g.means[3 * i]) +
                               q.normalized().toRotationMatrix() * offset;
  for (int a = 0; a < 3; ++a) {
    added->means[3 * j + a] = mean[a];
    added->log_scales[3 * j + a] -= std::log(shrink);
  }
}

void DensityStats::Reset(int n) {
  grad_sum.assign(n, 0.0);
  count.assign(n, 0.0);
  max_radius.assign(n, 0.0);
}

void DensityStats::AddView(int width, int height, const std::vector<int>& radii,
                           const std::vector<double>& mean2d_grads) {
  CHECK_EQ(static_cast<int>(radii.size()), size());
  CHECK_EQ(mean2d_grads.size(), 2 * radii.size());
  const double half_w = 0.5 * width, half_h = 0.5 * height;
  for (int i = 0; i < size(); ++i) {
    if (radii[i] <= 0) continue;
    grad_sum[i] += std::hypot(mean2d_grads[2 * i] * half_w,
                              mean2d_grads[2 * i + 1] * half_h);
    count[i] += 1;
    max_radius[i] = std::max(max_radius[i], static_cast<double>(radii[i]));
  }
}

void DensityStats::Add(const DensityStats& views) {
  CHECK_EQ(views.size(), size());
  for (int i = 0; i < size(); ++i) {
    grad_sum[i] += views.grad_sum[i];
    count[i] += views.count[i];
    max_radius[i] = std::max(max_radius[i], views.max_radius[i]);
  }
}

void DensityStats::Filter(const std::vector<bool>& keep) {
  CHECK_EQ(static_cast<int>(keep.size()), size());
  auto compact = [&keep](std::vector<double>& v) {
    size_t out = 0;
    for (size_t i = 0; i < keep.size(); ++i)
      if (keep[i]) v[out++] = v[i];
    v.resize(out);
  };
  compact(grad_sum);
  compact(count);
  compact(max_radius);
}

void DensityStats::AppendZeros(int n) {
  grad_sum.resize(grad_sum.size() + n, 0.0);
  count.resize(count.size() + n, 0.0);
  max_radius.resize(max_radius.size() + n, 0.0);
}

DensifyResult DensifyAndPrune(const DensifyOptions& options,
                              double scene_extent, bool prune_large,
                              std::mt19937_64* rng, GaussianSet* g,
                              GaussianAdam* adam, DensityStats* stats) {
  ScopedStage timer(Stage::kDensify);
  const int n = g->size();
  CHECK_EQ(stats->size(), n);
  DensifyResult result;

  // Candidates, highest gradient first so a capped budget goes to them.
  std::vector<int> candidates;
  for (int i = 0; i < n; ++i)
    if (stats->MeanGrad(i) >= options.grad_threshold) candidates.push_back(i);
  std::stable_sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return stats->MeanGrad(a) > stats->MeanGrad(b);
  });
  const int budget = std::max(0, options.max_gaussians - n);
  if (static_cast<int>(candidates.size()) > budget) candidates.resize(budget);

  // Each clone or split adds one Gaussian net.
  GaussianSet added;
  added.sh_degree = g->sh_degree;
  std::vector<bool> keep(n, true);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int i : candidates) {
    if (MaxScale(*g, i) <= options.percent_dense * scene_extent) {
      added.AppendFrom(*g, i);
      ++result.cloned;
      continue;
    }
    keep[i] = false;
    ++result.split;
    for (int s = 0; s < kSplitCount; ++s)
      AppendSampledChild(*g, i, 0.8 * kSplitCount, &normal, rng, &added);
  }

  g->Filter(keep);
  adam->Filter(keep);
  stats->Filter(keep);
  for (int j = 0; j < added.size(); ++j) g->AppendFrom(added, j);
  adam->AppendZeros(added.size());
  stats->AppendZeros(added.size());

  std::vector<bool> survive(g->size(), true);
  const double max_world = options.max_world_scale * scene_extent;
  for (int i = 0; i < g->size(); ++i) {
    bool prune = Sigmoid(g->opacity_logits[i]) < options.min_opacity;
    if (prune_large)
      prune = prune || stats->max_radius[i] > options.max_screen_radius ||
              (max_world > 0 && MaxScale(*g, i) > max_world);
    survive[i] = !prune;
    result.pruned += prune;
  }
  g->Filter(survive);
  adam->Filter(survive);
  stats->Reset(g->size());
  return result;
}

void ResetOpacity(double max_opacity, GaussianSet* g, GaussianAdam* adam) {
  const double cap = Logit(max_opacity);
  for (double& o : g->opacity_logits) o = std::min(o, cap);
  adam->ResetOpacityMoments();
}

}  // namespace es
