#ifndef EULERSPLAT_APPS_COMMON_FLAG_CHECKS_H_
#define EULERSPLAT_APPS_COMMON_FLAG_CHECKS_H_

#include <cstdint>
#include <string>

namespace es {

// Checks of one flag value each, run before any work. Each throws an
// InputError naming the flag, its value and the rule ("--track_count=-3:
// must be >= 1"). `flag` is the name without dashes.
void RequireFlag(const std::string& flag, const std::string& value);
void RequireAtLeast(const std::string& flag, int64_t value, int64_t min);
void RequireAtMost(const std::string& flag, int64_t value, int64_t max,
                   const std::string& why);
void RequireInRange(const std::string& flag, double value, double lo,
                    double hi);  // lo <= value <= hi
void RequireInOpenRange(const std::string& flag, double value, double lo,
                        double hi);  // lo < value < hi
void RequirePositive(const std::string& flag, double value);
void RequireNonNegative(const std::string& flag, double value);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_FLAG_CHECKS_H_
