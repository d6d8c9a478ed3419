#include "synth/noise.h"

#include <cmath>

namespace es {
namespace {

// Hash of a lattice point to [0, 1).
double LatticeValue(int64_t x, int64_t y, int64_t z, uint64_t seed) {
  uint64_t h = seed ^ 0x2545F4914F6CDD1Dull;
  for (int64_t v : {x, y, z}) {
    h ^= static_cast<uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) +
         (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

}  // namespace

double ValueNoise(const Eigen::Vector3d& p, uint64_t seed) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()),
               fz = std::floor(p.z());
  const int64_t x0 = static_cast<int64_t>(fx), y0 = static_cast<int64_t>(fy),
                z0 = static_cast<int64_t>(fz);
  const double tx = Fade(p.x() - fx), ty = Fade(p.y() - fy),
               tz = Fade(p.z() - fz);
  double result = 0.0;
  for (int dz = 0; dz < 2; ++dz) {
    for (int dy = 0; dy < 2; ++dy) {
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty) *
                         (dz ? tz : 1.0 - tz);
        result += w * LatticeValue(x0 + dx, y0 + dy, z0 + dz, seed);
      }
    }
  }
  return result;
}

double FractalNoise(const Eigen::Vector3d& p, int octaves, uint64_t seed) {
  double sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * ValueNoise(p * frequency, seed + 7919 * o);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

}  // namespace es
