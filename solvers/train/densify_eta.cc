#include "solvers/train/densify_eta.h"

#include <algorithm>

namespace es {

double DensifyingEta(const DensifyEtaInput& in) {
  const int64_t left = std::max<int64_t>(0, in.iterations - in.iteration);
  if (left == 0 || in.gaussians <= 0) {
    return left * in.seconds_per_iteration;
  }
  const double growth = std::max(0.0, in.growth_per_iteration);
  const int64_t growing = std::clamp<int64_t>(
      std::min(in.densify_end, in.iterations) - in.iteration, 0, left);
  const double cap = std::max(in.max_gaussians, in.gaussians);
  // Sum of the projected counts over the growing iterations, then the
  // final count over the rest.
  double gaussian_iterations = 0;
  double g = in.gaussians;
  for (int64_t k = 0; k < growing; ++k) {
    g = std::min(cap, g + growth);
    gaussian_iterations += g;
  }
  gaussian_iterations += static_cast<double>(left - growing) * g;
  return in.seconds_per_iteration / in.gaussians * gaussian_iterations;
}

}  // namespace es
