#include "apps/common/wait_policy.h"

#include <unistd.h>

#include <cstdlib>

namespace es {

bool WaitPolicyNeeded(const char* omp_wait_policy, const char* gomp_spincount,
                      const char* marker) {
  return omp_wait_policy == nullptr && gomp_spincount == nullptr &&
         marker == nullptr;
}

std::string WaitPolicyDescription(const char* omp_wait_policy,
                                  const char* gomp_spincount,
                                  const char* marker) {
  std::string out = "OpenMP wait policy: ";
  if (omp_wait_policy != nullptr)
    out += std::string("OMP_WAIT_POLICY=") + omp_wait_policy + ", ";
  if (gomp_spincount != nullptr)
    out += std::string("GOMP_SPINCOUNT=") + gomp_spincount + ", ";
  if (omp_wait_policy == nullptr && gomp_spincount == nullptr)
    return out + "libgomp's default (long spin)";
  const bool app = marker != nullptr && omp_wait_policy == nullptr &&
                   std::string(gomp_spincount) == kSpinCount;
  return out + (app ? "set by the app" : "the user's");
}

void ApplyWaitPolicy(char** argv, const ExecFunction& exec) {
  if (!WaitPolicyNeeded(std::getenv("OMP_WAIT_POLICY"),
                        std::getenv("GOMP_SPINCOUNT"),
                        std::getenv(kWaitPolicyMarker))) {
    return;
  }
  // The marker first: whatever happens below, the next image does not
  // come back here.
  if (::setenv(kWaitPolicyMarker, "1", 1) != 0) return;
  if (::setenv("GOMP_SPINCOUNT", kSpinCount, 1) != 0) return;
  if (exec) {
    exec(argv);
  } else {
    ::execv("/proc/self/exe", argv);
  }
  // The exec failed: go on with the default policy, as before.
  ::unsetenv("GOMP_SPINCOUNT");
}

}  // namespace es
