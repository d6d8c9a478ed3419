#ifndef EULERSPLAT_CORE_METRICS_RANDOM_DIRECTION_H_
#define EULERSPLAT_CORE_METRICS_RANDOM_DIRECTION_H_

#include <cmath>
#include <random>
#include <vector>

namespace es {

// Fills `dir` (its size is the dimension) with a direction drawn uniformly
// from the unit sphere: a normalized standard normal vector, the
// projections of a sliced Wasserstein distance. The caller keeps `normal`
// across draws, so a sequence of draws follows from the seed alone.
inline void DrawUnitDirection(std::mt19937_64* rng,
                              std::normal_distribution<double>* normal,
                              std::vector<double>* dir) {
  double norm = 0;
  for (double& c : *dir) {
    c = (*normal)(*rng);
    norm += c * c;
  }
  norm = std::sqrt(norm);
  for (double& c : *dir) c /= norm;
}

}  // namespace es

#endif  // EULERSPLAT_CORE_METRICS_RANDOM_DIRECTION_H_
