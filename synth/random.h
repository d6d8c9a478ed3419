#ifndef EULERSPLAT_SYNTH_RANDOM_H_
#define EULERSPLAT_SYNTH_RANDOM_H_

#include <cmath>
#include <cstdint>

namespace es {

// Small deterministic generator (SplitMix64) for the synthetic scenes. The
// std:: distributions are implementation-defined, so they could change a
// scene's bytes between standard libraries; this one cannot. One instance per
// particle keeps parallel simulation deterministic.
class SynthRandom {
 public:
  explicit SynthRandom(uint64_t seed = 0) : state_(seed) {}

  // A seed for an independent stream: mixes a parent seed with a stream id.
  static uint64_t Derive(uint64_t seed, uint64_t stream) {
    SynthRandom r(seed ^ (0x9E3779B97F4A7C15ull * (stream + 1)));
    r.Next();
    return r.Next();
  }

  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Standard normal (Box-Muller; uses two uniforms per call).
  double Normal() {
    const double u1 = 1.0 - Uniform();  // in (0, 1]: log is finite
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  uint64_t state_;
};

}  // namespace es

#endif  // EULERSPLAT_SYNTH_RANDOM_H_
