#ifndef EULERSPLAT_APPS_COMMON_VERSION_H_
#define EULERSPLAT_APPS_COMMON_VERSION_H_

#include <string>

namespace es {

// "eulersplat 0.1.0 (commit 1a2b3c4d5e6f)": the project version and the git
// commit the build was configured from ("unknown" outside a git checkout).
std::string VersionString();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_VERSION_H_
