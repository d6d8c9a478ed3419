#ifndef EULERSPLAT_TESTS_CUDA_TINY_LOOP_MODEL_H_
#define EULERSPLAT_TESTS_CUDA_TINY_LOOP_MODEL_H_

#include <random>

#include <Eigen/Core>

#include "core/loop/loop_model.h"
#include "tests/small_fields.h"

namespace es {
namespace cuda {

struct TinyLoopModelCase {
  const char* name;
  int sh_degree;
  bool motion, residual;
};

// frame_composer_test.cc's tiny model, larger, for the device loop tests
// (tiny, since the emulated device runs a thread per CUDA thread): 24
// Gaussians in front of a camera at the origin looking down +z, 10 of
// them dynamic, small fields (V moving points by velocity_scale of the
// box a step) whose outputs are far from zero.
inline LoopModel TinyLoopModel(const TinyLoopModelCase& c, int cycle_length,
                               double velocity_scale) {
  LoopModel m;
  m.cycle_length = cycle_length;
  GaussianSet& g = m.gaussians;
  g.sh_degree = c.sh_degree;
  g.Resize(24);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : g.means) v = 0.8 * u(rng);
  for (int n = 0; n < g.size(); ++n) g.means[3 * n + 2] += 4.0;
  for (double& v : g.log_scales) v = -2 + 0.2 * u(rng);
  for (double& v : g.opacity_logits) v = u(rng);
  for (double& v : g.sh) v = 0.5 * u(rng);
  m.dynamic_index = {1, 2, 4, 6, 9, 11, 15, 18, 20, 23};
  for (int start : {0, 3, 1, 2, 2, 0, 3, 1, 0, 2})
    m.start_times.push_back(start % cycle_length);
  const Eigen::Vector3d lo(-1, -1, 3), hi(1, 1, 5);
  if (c.motion) {
    MotionFieldOptions o = SmallMotionFieldOptions(velocity_scale);
    o.seed = 5;
    m.motion.emplace(o);
    m.motion->SetBox(lo, hi);
  }
  if (c.residual) {
    ResidualFieldOptions o = SmallResidualFieldOptions(cycle_length);
    o.mlp_depth = 1;
    o.last_layer_init_scale = 1.0;
    o.seed = 7;
    m.residual.emplace(o);
    m.residual->SetBox(lo, hi);
  }
  return m;
}

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_TESTS_CUDA_TINY_LOOP_MODEL_H_
