#ifndef EULERSPLAT_TESTS_RANDOM_SCENE_FLOW_SAMPLES_H_
#define EULERSPLAT_TESTS_RANDOM_SCENE_FLOW_SAMPLES_H_

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/flow/flow_lifting.h"

namespace es {

// n samples at positions uniform in [-extent, extent]^3 with velocities
// uniform in [-extent, extent]^3 * speed; one in three has a random unit
// unseen direction (a facing-plane sample's free line of sight), one in
// three such a direction of length 0.6 (a partial weight), the rest none.
inline std::vector<SceneFlowSample> RandomSceneFlowSamples(int n,
                                                           uint32_t seed,
                                                           double extent,
                                                           double speed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<SceneFlowSample> samples(n);
  for (int i = 0; i < n; ++i) {
    SceneFlowSample& s = samples[i];
    s.x = Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.v = speed * Eigen::Vector3d(u(rng), u(rng), u(rng));
    if (i % 3 != 0) {
      s.unseen = Eigen::Vector3d(u(rng), u(rng), 1.0).normalized();
      if (i % 3 == 2) s.unseen *= 0.6;
    }
  }
  return samples;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_RANDOM_SCENE_FLOW_SAMPLES_H_
