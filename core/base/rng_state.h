#ifndef EULERSPLAT_CORE_BASE_RNG_STATE_H_
#define EULERSPLAT_CORE_BASE_RNG_STATE_H_

#include <random>
#include <sstream>
#include <string>

namespace es {

// std::mt19937_64 in its standard text form, as checkpoints store it, so a
// resumed run draws exactly the numbers the killed one would have.
inline std::string RngState(const std::mt19937_64& rng) {
  std::ostringstream out;
  out << rng;
  return out.str();
}

// Returns false (leaving *rng unspecified) on a malformed state.
inline bool RestoreRngState(const std::string& state, std::mt19937_64* rng) {
  std::istringstream in(state);
  in >> *rng;
  return !in.fail();
}

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_RNG_STATE_H_
