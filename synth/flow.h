#ifndef EULERSPLAT_SYNTH_FLOW_H_
#define EULERSPLAT_SYNTH_FLOW_H_

#include <variant>

#include <Eigen/Core>

namespace es {

// Analytic, time-independent, smooth (C-infinity) velocity fields that drive
// the synthetic water. World y is up; velocities are in world units per
// frame. They are deliberately unlike the reconstruction model (no triplane,
// no MLP, no periodic cycle) so the benchmark does not favour it.

// A pool surface: pulls water to the surface height, spreads it radially
// from an impact point and lets it drift downstream.
struct PoolFlow {
  double surface_y = 0.0;
  double relax = 0.2;              // 1/frame: pull toward the surface
  Eigen::Vector2d center{0, 0};    // impact point (x, z)
  double spread_speed = 0.03;      // peak radial speed, reached at `radius`
  double radius = 1.0;
  Eigen::Vector3d drift{0, 0, 0};  // downstream drift (y ignored)

  Eigen::Vector3d Velocity(const Eigen::Vector3d& x) const;
};

// Water leaves a cliff lip at `lip_y` moving away from the wall (+z),
// accelerates under gravity while fanning out slightly, then blends into a
// pool below `blend_y`.
struct WaterfallFlow {
  double lip_y = 3.0;
  double lip_x = 0.0;           // center of the fall in x
  double exit_speed = 0.03;     // +z speed over the lip
  double initial_fall_speed = 0.02;
  double gravity = 0.011;       // 9.8 m/s^2 at 30 frames/s
  double fan_out = 0.004;       // 1/frame: lateral divergence of the curtain
  double blend_y = 0.4;         // fall-to-pool transition height
  double blend_width = 0.12;
  PoolFlow pool;

  Eigen::Vector3d Velocity(const Eigen::Vector3d& x) const;
};

// Water in a channel along +x: fastest on the center line, meandering
// sideways, held to a gently sloping surface.
struct StreamFlow {
  double speed = 0.07;              // center-line speed
  double half_width = 1.0;          // channel half width (z)
  double center_z = 0.0;
  double meander = 0.25;            // sideways speed / speed
  double meander_frequency = 0.9;   // rad per world unit along x
  double speed_ripple = 0.25;       // relative speed variation along x
  double surface_y = 0.08;          // surface height at x = 0
  double slope = 0.02;              // surface drop per unit x
  double relax = 0.15;              // 1/frame
  double centering = 0.004;         // 1/frame: keeps water in the channel

  Eigen::Vector3d Velocity(const Eigen::Vector3d& x) const;
};

// A vertical jet from a nozzle that slows as it rises, opens into an
// umbrella near the top, falls outside the core under gravity and lands in
// a basin.
struct FountainFlow {
  Eigen::Vector3d nozzle{0, 0.2, 0};
  double jet_speed = 0.16;       // upward speed at the nozzle
  double jet_height = 2.0;       // height at which the core stalls
  double core_radius = 0.22;
  double umbrella_speed = 0.035; // outward speed outside the core
  double gravity = 0.011;
  double blend_y = 0.45;         // air-to-basin transition height
  double blend_width = 0.1;
  PoolFlow pool;

  Eigen::Vector3d Velocity(const Eigen::Vector3d& x) const;
};

// One of the presets' fields.
class SynthFlow {
 public:
  using Field = std::variant<WaterfallFlow, StreamFlow, FountainFlow>;
  SynthFlow() = default;
  explicit SynthFlow(Field field) : field_(std::move(field)) {}

  Eigen::Vector3d Velocity(const Eigen::Vector3d& x) const {
    return std::visit([&x](const auto& f) { return f.Velocity(x); }, field_);
  }

 private:
  Field field_;
};

}  // namespace es

#endif  // EULERSPLAT_SYNTH_FLOW_H_
