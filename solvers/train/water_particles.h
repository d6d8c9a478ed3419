#ifndef EULERSPLAT_SOLVERS_TRAIN_WATER_PARTICLES_H_
#define EULERSPLAT_SOLVERS_TRAIN_WATER_PARTICLES_H_

#include <cstdint>
#include <vector>

#include "core/io/scene.h"
#include "core/model/gaussians.h"

namespace es {

// Water made of particles instead of blobs. The static stage fits the
// time-averaged water with a few large translucent Gaussians; advected by
// V they slide as smooth sheets and the loop looks like a blur. Splitting
// them into many small particles before joint training (and keeping them
// small) gives V something to move that looks like droplets and streaks.
//
// Sizes are in pixels (standard deviation on screen at the Gaussian's
// depth from the training cameras), so the same setting fits any scene
// scale and resolution.

struct WaterParticleOptions {
  double particle_pixels = 1.5;  // target particle std dev on screen
  int max_children = 16;         // particles per split blob
  int max_particles = 20000;     // total dynamic budget after the split
  double dynamic_threshold = 0.2;  // sigmoid(dynamic_logit) > this: water
  uint64_t seed = 0;
};

// World-space std dev that projects to `pixels` for each listed Gaussian:
// its mean distance to the training cameras' centers times pixels / mean
// fx.
std::vector<double> PixelSizeInWorld(const GaussianSet& g,
                                     const std::vector<int>& indices,
                                     const std::vector<Frame>& frames,
                                     const std::vector<int>& train,
                                     double pixels);

struct ParticleSplitStats {
  int blobs = 0;      // dynamic Gaussians replaced
  int particles = 0;  // particles added for them
  int dynamic_before = 0, dynamic_after = 0;
};

// Replaces every dynamic Gaussian larger than the target size by particles
// drawn from its own 3D normal distribution (so together they fill its
// volume), each with the target size on all axes, the blob's color,
// opacity and water probability. The number of particles per blob grows
// with its screen area over a particle's (at most max_children), scaled
// down uniformly to stay within max_particles. Static Gaussians are kept
// as they are, first, in their order; the particles are appended.
ParticleSplitStats SplitWaterIntoParticles(const WaterParticleOptions& options,
                                           const std::vector<Frame>& frames,
                                           const std::vector<int>& train,
                                           GaussianSet* g);

// Caps the log-scales of the given Gaussians at log(max_scale[k]) (one
// bound per listed Gaussian); returns how many values were clamped.
int ClampScales(const std::vector<int>& indices,
                const std::vector<double>& max_scale, GaussianSet* g);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_WATER_PARTICLES_H_
