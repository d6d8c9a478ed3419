#include "apps/common/version.h"

// Both come from CMake at configure time (CMakeLists.txt); the fallbacks
// keep a build outside CMake compiling.
#ifndef ES_VERSION
#define ES_VERSION "unknown"
#endif
#ifndef ES_GIT_COMMIT
#define ES_GIT_COMMIT "unknown"
#endif

namespace es {

std::string VersionString() {
  return std::string("eulersplat ") + ES_VERSION + " (commit " + ES_GIT_COMMIT +
         ")";
}

}  // namespace es
