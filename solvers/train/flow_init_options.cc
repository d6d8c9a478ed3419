#include "solvers/train/flow_init_options.h"

#include "core/base/input_error.h"

namespace es {

std::optional<TruthPart> ParseOracleVelocity(const std::string& name) {
  if (name == "none") return std::nullopt;
  if (name == "seen") return TruthPart::kSeen;
  if (name == "full") return TruthPart::kFull;
  throw InputError("--oracle_velocity must be none, seen or full, not '" +
                   name + "'");
}

std::string OracleVelocityName(const std::optional<TruthPart>& oracle) {
  if (!oracle) return "none";
  return *oracle == TruthPart::kSeen ? "seen" : "full";
}

}  // namespace es
