#ifndef EULERSPLAT_SYNTH_NOISE_H_
#define EULERSPLAT_SYNTH_NOISE_H_

#include <cstdint>

#include <Eigen/Core>

namespace es {

// Smooth 3D value noise in [0, 1]: random values on the integer lattice,
// blended with a quintic fade so the field and its gradient are continuous.
double ValueNoise(const Eigen::Vector3d& p, uint64_t seed);

// Fractal sum of `octaves` value-noise layers, each twice the frequency and
// half the amplitude of the last; normalized to [0, 1]. Used for the
// multi-scale texture that gives structure-from-motion features to match.
double FractalNoise(const Eigen::Vector3d& p, int octaves, uint64_t seed);

}  // namespace es

#endif  // EULERSPLAT_SYNTH_NOISE_H_
