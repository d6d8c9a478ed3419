#include "apps/common/flag_checks.h"

#include <cmath>

#include "core/base/input_error.h"
#include "core/base/number_text.h"

namespace es {
namespace {

[[noreturn]] void Fail(const std::string& flag, const std::string& value,
                       const std::string& rule) {
  throw InputError("--" + flag + "=" + value + ": " + rule);
}

}  // namespace

void RequireFlag(const std::string& flag, const std::string& value) {
  if (value.empty()) throw InputError("--" + flag + " is required");
}

void RequireAtLeast(const std::string& flag, int64_t value, int64_t min) {
  if (value < min) {
    Fail(flag, std::to_string(value), "must be >= " + std::to_string(min));
  }
}

void RequireAtMost(const std::string& flag, int64_t value, int64_t max,
                   const std::string& why) {
  if (value > max) {
    Fail(flag, std::to_string(value),
         "must be <= " + std::to_string(max) + " (" + why + ")");
  }
}

void RequireInRange(const std::string& flag, double value, double lo,
                    double hi) {
  if (!(value >= lo && value <= hi)) {
    Fail(flag, ShortNumber(value),
         "must be in [" + ShortNumber(lo) + ", " + ShortNumber(hi) + "]");
  }
}

void RequireInOpenRange(const std::string& flag, double value, double lo,
                        double hi) {
  if (!(value > lo && value < hi)) {
    Fail(flag, ShortNumber(value),
         "must be in (" + ShortNumber(lo) + ", " + ShortNumber(hi) + ")");
  }
}

void RequirePositive(const std::string& flag, double value) {
  if (!(value > 0)) Fail(flag, ShortNumber(value), "must be > 0");
}

void RequireNonNegative(const std::string& flag, double value) {
  if (!(value >= 0)) Fail(flag, ShortNumber(value), "must be >= 0");
}

}  // namespace es
