#ifndef EULERSPLAT_TESTS_WATER_LOOP_FIXTURE_H_
#define EULERSPLAT_TESTS_WATER_LOOP_FIXTURE_H_

#include <cmath>
#include <random>

#include "core/loop/cycle_time.h"
#include "core/model/camera.h"
#include "core/loop/loop_model.h"
#include "core/viz/camera_path.h"
#include "tests/centered_camera.h"
#include "tests/small_fields.h"

namespace es {

// A small looping scene with a static half and a water half, for the export
// tests: opaque static splats on a wall at x < -0.1, water splats at
// x > 0.1 in front of it, moved by a motion field fast enough to shift them
// by pixels within a loop and recolored by a residual field.
constexpr int kWaterLoopLength = 6;

inline Camera WaterLoopCamera() {
  // Not aimed at the origin, where viewers like to point a camera.
  return LookAt(CenteredCamera(192, 128, 160), {0.4, -0.3, -3.2}, {0.2, 0.1, 0},
                {0, -1, 0});
}

inline LoopModel WaterLoopModel(int sh_degree = 1) {
  LoopModel m;
  m.cycle_length = kWaterLoopLength;
  m.gaussians.sh_degree = sh_degree;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 900;
  m.gaussians.Resize(n);
  const int k_count = m.gaussians.sh_coeffs();
  for (int i = 0; i < n; ++i) {
    const bool water = i % 2 == 1;
    double* mean = &m.gaussians.means[3 * i];
    mean[0] = water ? 0.1 + 0.9 * u(rng) : -1.0 + 0.9 * u(rng);
    mean[1] = -0.6 + 1.2 * u(rng);
    mean[2] = water ? -0.3 + 0.3 * u(rng) : 0.2 + 0.5 * u(rng);
    for (int j = 0; j < 3; ++j) {
      m.gaussians.log_scales[3 * i + j] = std::log(water ? 0.05 : 0.07);
      m.gaussians.sh[3 * k_count * i + j] = 3.0 * (u(rng) - 0.5);
    }
    for (int k = 3; k < 3 * k_count; ++k)
      m.gaussians.sh[3 * k_count * i + k] = 0.2 * (u(rng) - 0.5);
    m.gaussians.opacity_logits[i] = water ? 1.5 : 4.0;
    m.gaussians.dynamic_logits[i] = water ? 3.0 : -3.0;
    if (water) m.dynamic_index.push_back(i);
  }
  m.start_times = RandomStartTimes(m.num_dynamic(), kWaterLoopLength, 3);
  m.motion.emplace(SmallMotionFieldOptions(0.02));
  m.motion->SetBox({-1, -1, -1}, {1, 1, 1});
  m.motion->Initialize(5);
  m.residual.emplace(SmallResidualFieldOptions(kWaterLoopLength));
  m.residual->SetBox({-1, -1, -1}, {1, 1, 1});
  m.residual->Initialize(6);
  return m;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_WATER_LOOP_FIXTURE_H_
