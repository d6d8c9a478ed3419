#include "solvers/train/water_particles.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <glog/logging.h>

namespace es {

std::vector<double> PixelSizeInWorld(const GaussianSet& g,
                                     const std::vector<int>& indices,
                                     const std::vector<Frame>& frames,
                                     const std::vector<int>& train,
                                     double pixels) {
  CHECK(!train.empty());
  std::vector<Eigen::Vector3d> centers;
  double fx = 0;
  for (int i : train) {
    centers.push_back(frames[i].camera.Center());
    fx += frames[i].camera.fx;
  }
  fx /= train.size();
  std::vector<double> out(indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    const Eigen::Vector3d x(&g.means[3 * indices[k]]);
    double distance = 0;
    for (const Eigen::Vector3d& c : centers) distance += (x - c).norm();
    out[k] = pixels * distance / centers.size() / fx;
  }
  return out;
}

ParticleSplitStats SplitWaterIntoParticles(const WaterParticleOptions& options,
                                           const std::vector<Frame>& frames,
                                           const std::vector<int>& train,
                                           GaussianSet* g) {
  CHECK_GT(options.particle_pixels, 0);
  CHECK_GE(options.max_children, 1);
  std::vector<int> all(g->size());
  for (int n = 0; n < g->size(); ++n) all[n] = n;
  const std::vector<double> target =
      PixelSizeInWorld(*g, all, frames, train, options.particle_pixels);
  ParticleSplitStats stats;
  // How many particles each large water blob would like.
  std::vector<int> want(g->size(), 0);
  long long wanted = 0;
  for (int n = 0; n < g->size(); ++n) {
    if (Sigmoid(g->dynamic_logits[n]) <= options.dynamic_threshold) continue;
    ++stats.dynamic_before;
    double s[3];
    for (int a = 0; a < 3; ++a) s[a] = std::exp(g->log_scales[3 * n + a]);
    std::sort(s, s + 3);
    if (s[2] <= target[n]) continue;
    // Screen area of the blob (two largest axes) over a particle's.
    const double area = s[2] * std::max(s[1], target[n]) /
                        (target[n] * target[n]);
    want[n] = std::clamp(static_cast<int>(std::ceil(area)), 2,
                         options.max_children);
    wanted += want[n];
  }
  // Budget: the blobs' particles plus the dynamic Gaussians kept as they are.
  const long long split = std::count_if(want.begin(), want.end(),
                                        [](int w) { return w > 0; });
  const long long kept = stats.dynamic_before - split;
  double share = 1.0;
  if (wanted > 0 && wanted + kept > options.max_particles) {
    share = std::max(0.0, static_cast<double>(options.max_particles - kept)) /
            wanted;
  }

  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal;
  GaussianSet out;
  out.sh_degree = g->sh_degree;
  std::vector<int> blobs;
  for (int n = 0; n < g->size(); ++n) {
    if (want[n] == 0) {
      out.AppendFrom(*g, n);
    } else {
      blobs.push_back(n);
    }
  }
  for (int n : blobs) {
    ++stats.blobs;
    const int children =
        std::max(1, static_cast<int>(std::lround(want[n] * share)));
    const Eigen::Quaterniond q(g->quats[4 * n], g->quats[4 * n + 1],
                               g->quats[4 * n + 2], g->quats[4 * n + 3]);
    const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
    const Eigen::Vector3d scale(std::exp(g->log_scales[3 * n]),
                                std::exp(g->log_scales[3 * n + 1]),
                                std::exp(g->log_scales[3 * n + 2]));
    const Eigen::Vector3d mean(&g->means[3 * n]);
    for (int c = 0; c < children; ++c) {
      out.AppendFrom(*g, n);
      const int k = out.size() - 1;
      const Eigen::Vector3d z(normal(rng), normal(rng), normal(rng));
      const Eigen::Vector3d x = mean + r * scale.cwiseProduct(z);
      for (int a = 0; a < 3; ++a) {
        out.means[3 * k + a] = x[a];
        out.log_scales[3 * k + a] =
            std::log(std::min(scale[a], target[n]));
      }
      ++stats.particles;
    }
  }
  stats.dynamic_after = static_cast<int>(kept) + stats.particles;
  *g = std::move(out);
  return stats;
}

int ClampScales(const std::vector<int>& indices,
                const std::vector<double>& max_scale, GaussianSet* g) {
  CHECK_EQ(indices.size(), max_scale.size());
  int clamped = 0;
  for (size_t k = 0; k < indices.size(); ++k) {
    const double bound = std::log(max_scale[k]);
    for (int a = 0; a < 3; ++a) {
      double& s = g->log_scales[3 * indices[k] + a];
      if (s > bound) {
        s = bound;
        ++clamped;
      }
    }
  }
  return clamped;
}

}  // namespace es
