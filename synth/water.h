#ifndef EULERSPLAT_SYNTH_WATER_H_
#define EULERSPLAT_SYNTH_WATER_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/model/gaussians.h"
#include "synth/flow.h"
#include "synth/random.h"

namespace es {

// How water particles look when turned into Gaussians: small, bright, foamy
// and translucent, stretched along their motion like a short exposure.
struct WaterLook {
  double size = 0.03;     // std dev across the motion (world units)
  double streak = 0.5;    // std dev along the motion += streak * speed
  double min_opacity = 0.25, max_opacity = 0.7;
  Eigen::Vector3d deep_color{0.40, 0.56, 0.66};
  Eigen::Vector3d foam_color{0.96, 0.98, 1.0};
  // Fast water is white with foam, slow water shows its deep color: the
  // foam share grows with speed up to this speed (world units per frame).
  double foam_speed = 0.1;
  double fade_frames = 3.0;  // opacity ramps in at birth and out at death
  // The sun's glint on each droplet's tumbling facet, as a path tracer
  // renders water: seen only near the mirror direction, so droplets
  // sparkle and flicker as they fall and as the camera moves. Added
  // brightness at a perfect reflection (0: off, the plain splat look).
  double glint = 0.0;
  double glint_exponent = 60.0;  // Phong exponent: how narrow a glint is
  double glint_spin = 0.4;       // facet rotation, radians per frame
  Eigen::Vector3d sun_direction{-0.4, 0.8, 0.45};  // towards the sun
};

// Where and when one render sees the water: the eye (for glints) and the
// time within the frame (frames; motion blur renders several).
struct WaterShot {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  double time_offset = 0.0;
};

struct WaterSimOptions {
  int num_particles = 20000;
  int substeps = 4;              // RK4 steps per frame
  double stochasticity = 1.0;    // 0: smooth steady flow
  // At stochasticity 1, each particle's velocity is perturbed by a random
  // (Ornstein-Uhlenbeck) factor with this std, relative to the local speed.
  double turbulence = 0.15;
  double turbulence_frames = 4.0;  // correlation time of the perturbation
  double min_lifetime = 60.0, max_lifetime = 100.0;  // frames
  Eigen::AlignedBox3d region;      // particles leaving it respawn
  Eigen::AlignedBox3d source;      // particles are born uniformly in it
  uint64_t seed = 1;
};

struct WaterParticle {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d perturbation = Eigen::Vector3d::Zero();  // relative
  double age = 0, lifetime = 0;
  double delay = 0;     // frames until first birth; active when <= 0
  int generation = 0;   // number of births so far
  double size = 1, opacity = 1, foam = 1;  // per-particle look factors
  SynthRandom random;

  bool active() const { return delay <= 0; }
};

// A continuous stream of particles emitted at a source, advected through a
// smooth analytic field with RK4 plus a per-particle random perturbation,
// and reborn at the source when they leave the region or age out. Births
// are staggered at random and lifetimes drawn per birth, so there is no
// fixed cycle. Deterministic for a seed (one random stream per particle).
class WaterSim {
 public:
  WaterSim(const SynthFlow& flow, const WaterSimOptions& options);

  // Advances time by 1 / substeps frame.
  void Substep();
  void AdvanceFrames(int frames);

  double dt() const { return 1.0 / options_.substeps; }
  const std::vector<WaterParticle>& particles() const { return particles_; }
  // Active particles as Gaussians (dynamic logit high: water), each moved
  // by shot.time_offset frames along the field.
  GaussianSet ToGaussians(const WaterLook& look,
                          const WaterShot& shot = WaterShot()) const;

 private:
  void Spawn(WaterParticle* p) const;
  double Glint(const WaterLook& look, const WaterParticle& p, int index,
               const Eigen::Vector3d& to_eye) const;
  Eigen::Vector3d Rk4Step(const Eigen::Vector3d& x, double h) const;

  SynthFlow flow_;
  WaterSimOptions options_;
  std::vector<WaterParticle> particles_;
};

}  // namespace es

#endif  // EULERSPLAT_SYNTH_WATER_H_
