#ifndef EULERSPLAT_APPS_COMMON_PARSE_COLOR_H_
#define EULERSPLAT_APPS_COMMON_PARSE_COLOR_H_

#include <Eigen/Core>
#include <string>

namespace es {

// Parses "r,g,b" (three numbers); throws InputError naming `flag`.
Eigen::Vector3d ParseColor(const std::string& text, const std::string& flag);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_PARSE_COLOR_H_
