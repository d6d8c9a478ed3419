#include "synth/flow.h"

#include <cmath>

namespace es {
namespace {

// Smooth max(d, 0) with a ~1/sharpness wide knee; stable for large |d|.
double SoftPlus(double d, double sharpness = 20.0) {
  const double k = sharpness * d;
  return (k > 0 ? d : 0.0) + std::log1p(std::exp(-std::abs(k))) / sharpness;
}

// Smooth step from 0 (y << center) to 1 (y >> center).
double Blend(double y, double center, double width) {
  return 0.5 * (1.0 + std::tanh((y - center) / width));
}

// Downward speed of water that started falling at `top` with speed v0.
double FallSpeed(double y, double top, double v0, double gravity) {
  return std::sqrt(v0 * v0 + 2.0 * gravity * SoftPlus(top - y));
}

}  // namespace

Eigen::Vector3d PoolFlow::Velocity(const Eigen::Vector3d& x) const {
  const Eigen::Vector2d d(x.x() - center.x(), x.z() - center.y());
  const double q = d.squaredNorm() / (radius * radius);
  // Peak speed `spread_speed` at |d| = radius, slowing further out.
  const Eigen::Vector2d h = spread_speed * 2.0 / (1.0 + q) * d / radius;
  return {h.x() + drift.x(), -relax * (x.y() - surface_y), h.y() + drift.z()};
}

Eigen::Vector3d WaterfallFlow::Velocity(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d fall(
      fan_out * (x.x() - lip_x),
      -FallSpeed(x.y(), lip_y, initial_fall_speed, gravity), exit_speed);
  const double w = Blend(x.y(), blend_y, blend_width);
  return w * fall + (1.0 - w) * pool.Velocity(x);
}

Eigen::Vector3d StreamFlow::Velocity(const Eigen::Vector3d& x) const {
  const double s = (x.z() - center_z) / half_width;
  const double phase = meander_frequency * x.x();
  const double u = speed * (0.55 + 0.45 * std::exp(-s * s)) *
                   (1.0 + speed_ripple * std::sin(phase + 1.3));
  const double lateral =
      meander * speed * std::cos(phase) - centering * (x.z() - center_z);
  const double surface = surface_y - slope * x.x();
  return {u, -relax * (x.y() - surface), lateral};
}

Eigen::Vector3d FountainFlow::Velocity(const Eigen::Vector3d& x) const {
  const Eigen::Vector2d r_vec(x.x() - nozzle.x(), x.z() - nozzle.z());
  const double r2 = r_vec.squaredNorm();
  const double core = std::exp(-r2 / (core_radius * core_radius));
  const double h = (x.y() - nozzle.y()) / jet_height;
  const double top = nozzle.y() + jet_height;

  // Core: rises, decelerating linearly to a stall at the top. Outside: falls.
  const double up = jet_speed * (1.0 - h);
  const double down = -FallSpeed(x.y(), top, 0.01, gravity);
  const double vy = core * up + (1.0 - core) * down;
  // Outward: slow drift low in the core, opening near the top, full speed
  // outside the core (a projectile keeps its horizontal speed).
  const double opening = 0.1 + 0.9 * Blend(h, 0.85, 0.08);
  const double radial = umbrella_speed * (1.0 - core * (1.0 - opening));
  const Eigen::Vector2d out =
      radial * r_vec / std::sqrt(r2 + 0.05 * 0.05);
  const Eigen::Vector3d air(out.x(), vy, out.y());

  // The basin takes over low down, except inside the jet.
  const double w =
      1.0 - (1.0 - Blend(x.y(), blend_y, blend_width)) * (1.0 - core);
  return w * air + (1.0 - w) * pool.Velocity(x);
}

}  // namespace es
