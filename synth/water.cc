#include "synth/water.h"

#include <algorithm>
#include <cmath>

#include <glog/logging.h>

namespace es {
namespace {

// Logit of the water probability given to every water Gaussian.
constexpr double kWaterDynamicLogit = 6.0;
constexpr int kMinParallelParticles = 4096;
// Particles fainter than this are left out of the Gaussian set.
constexpr double kMinVisibleOpacity = 1.0 / 255.0;

double SmoothRamp(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace

WaterSim::WaterSim(const SynthFlow& flow, const WaterSimOptions& options)
    : flow_(flow), options_(options) {
  CHECK_GT(options.num_particles, 0);
  CHECK_GT(options.substeps, 0);
  CHECK_GE(options.stochasticity, 0.0);
  CHECK_GT(options.min_lifetime, 0.0);
  CHECK_GE(options.max_lifetime, options.min_lifetime);
  particles_.resize(options.num_particles);
  for (int i = 0; i < options.num_particles; ++i) {
    WaterParticle& p = particles_[i];
    p.random = SynthRandom(SynthRandom::Derive(options.seed, i));
    // Staggered first births give a continuous stream from the start.
    p.delay = p.random.Uniform(0.0, options.max_lifetime) + 1e-9;
  }
}

void WaterSim::Spawn(WaterParticle* p) const {
  SynthRandom& r = p->random;
  const Eigen::Vector3d lo = options_.source.min();
  const Eigen::Vector3d hi = options_.source.max();
  p->position = {r.Uniform(lo.x(), hi.x()), r.Uniform(lo.y(), hi.y()),
                 r.Uniform(lo.z(), hi.z())};
  // Start in the perturbation's stationary distribution.
  const double sigma = options_.turbulence * options_.stochasticity;
  p->perturbation = {sigma * r.Normal(), sigma * r.Normal(),
                     sigma * r.Normal()};
  p->age = 0.0;
  p->lifetime = r.Uniform(options_.min_lifetime, options_.max_lifetime);
  p->size = r.Uniform(0.6, 1.4);
  p->opacity = r.Uniform(0.0, 1.0);
  p->foam = r.Uniform(0.0, 1.0);
  ++p->generation;
}

Eigen::Vector3d WaterSim::Rk4Step(const Eigen::Vector3d& x, double h) const {
  const Eigen::Vector3d k1 = flow_.Velocity(x);
  const Eigen::Vector3d k2 = flow_.Velocity(x + 0.5 * h * k1);
  const Eigen::Vector3d k3 = flow_.Velocity(x + 0.5 * h * k2);
  const Eigen::Vector3d k4 = flow_.Velocity(x + h * k3);
  return x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

void WaterSim::Substep() {
  const double h = dt();
  const double sigma = options_.turbulence * options_.stochasticity;
  // Exact Ornstein-Uhlenbeck update: keeps the perturbation's std at sigma.
  const double decay = std::exp(-h / options_.turbulence_frames);
  const double kick = sigma * std::sqrt(1.0 - decay * decay);
  const int n = static_cast<int>(particles_.size());
  // Small sets run serially: a parallel region per sub-step costs more.
#pragma omp parallel for schedule(static) if (n > kMinParallelParticles)
  for (int i = 0; i < n; ++i) {
    WaterParticle& p = particles_[i];
    if (!p.active()) {
      p.delay -= h;
      if (p.active()) Spawn(&p);
      continue;
    }
    Eigen::Vector3d next = Rk4Step(p.position, h);
    if (sigma > 0.0) {
      const double speed = flow_.Velocity(p.position).norm();
      next += h * speed * p.perturbation;
      SynthRandom& r = p.random;
      p.perturbation = decay * p.perturbation +
                       kick * Eigen::Vector3d(r.Normal(), r.Normal(),
                                              r.Normal());
    }
    p.position = next;
    p.age += h;
    if (p.age > p.lifetime || !options_.region.contains(p.position)) {
      Spawn(&p);
    }
  }
}

// Random streams of the glints' facets, apart from the particles' own.
constexpr uint64_t kGlintStream = uint64_t{1} << 48;

// The glint particle `index` shows towards `to_eye`: the sun mirrored by
// a facet that tumbles at its own rate about its own axis, both drawn anew
// at each birth.
double WaterSim::Glint(const WaterLook& look, const WaterParticle& p,
                       int index, const Eigen::Vector3d& to_eye) const {
  const uint64_t birth = (static_cast<uint64_t>(index) << 20) +
                         static_cast<uint64_t>(p.generation);
  SynthRandom r(SynthRandom::Derive(options_.seed, kGlintStream + birth));
  const Eigen::Vector3d axis =
      Eigen::Vector3d(r.Normal(), r.Normal(), r.Normal()).normalized();
  const Eigen::Vector3d facet0 =
      Eigen::Vector3d(r.Normal(), r.Normal(), r.Normal()).normalized();
  const double angle = look.glint_spin * r.Uniform(0.5, 1.5) * p.age;
  Eigen::Vector3d facet = Eigen::AngleAxisd(angle, axis) * facet0;
  const Eigen::Vector3d sun = look.sun_direction.normalized();
  if (facet.dot(sun) < 0.0) facet = -facet;  // a droplet has two sides
  const Eigen::Vector3d mirrored = 2.0 * facet.dot(sun) * facet - sun;
  const double cosine = mirrored.dot(to_eye.normalized());
  return cosine > 0.0 ? look.glint * std::pow(cosine, look.glint_exponent)
                      : 0.0;
}

void WaterSim::AdvanceFrames(int frames) {
  for (int i = 0; i < frames * options_.substeps; ++i) Substep();
}

GaussianSet WaterSim::ToGaussians(const WaterLook& look,
                                  const WaterShot& shot) const {
  CHECK(look.min_opacity > 0.0 && look.max_opacity < 1.0);
  GaussianSet g;
  std::vector<int> visible;
  std::vector<double> opacities;
  for (int i = 0; i < static_cast<int>(particles_.size()); ++i) {
    const WaterParticle& p = particles_[i];
    if (!p.active()) continue;
    const double fade = SmoothRamp(p.age / look.fade_frames) *
                        SmoothRamp((p.lifetime - p.age) / look.fade_frames);
    const double opacity =
        fade * (look.min_opacity +
                (look.max_opacity - look.min_opacity) * p.opacity);
    if (opacity < kMinVisibleOpacity) continue;
    visible.push_back(i);
    opacities.push_back(opacity);
  }
  g.Resize(static_cast<int>(visible.size()));
  for (int k = 0; k < static_cast<int>(visible.size()); ++k) {
    const WaterParticle& p = particles_[visible[k]];
    const Eigen::Vector3d v = flow_.Velocity(p.position);
    const double speed = v.norm();
    const double across = look.size * p.size;
    const double along = std::hypot(across, look.streak * speed);
    const Eigen::Quaterniond q =
        speed > 1e-12
            ? Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), v)
            : Eigen::Quaterniond::Identity();
    const Eigen::Vector3d position = p.position + shot.time_offset * v;
    for (int a = 0; a < 3; ++a) g.means[3 * k + a] = position[a];
    g.log_scales[3 * k] = std::log(along);
    g.log_scales[3 * k + 1] = std::log(across);
    g.log_scales[3 * k + 2] = std::log(across);
    g.quats[4 * k] = q.w();
    g.quats[4 * k + 1] = q.x();
    g.quats[4 * k + 2] = q.y();
    g.quats[4 * k + 3] = q.z();
    g.opacity_logits[k] = Logit(opacities[k]);
    const double foam =
        std::min(1.0, 0.3 + 0.7 * speed / look.foam_speed) *
        (0.5 + 0.5 * p.foam);
    Eigen::Vector3d color =
        look.deep_color + foam * (look.foam_color - look.deep_color);
    if (look.glint > 0.0) {
      color += Eigen::Vector3d::Constant(
          Glint(look, p, visible[k], shot.eye - position));
    }
    for (int c = 0; c < 3; ++c) g.sh[3 * k + c] = (color[c] - 0.5) / kShC0;
    g.dynamic_logits[k] = kWaterDynamicLogit;
  }
  return g;
}

}  // namespace es
