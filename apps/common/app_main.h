#ifndef EULERSPLAT_APPS_COMMON_APP_MAIN_H_
#define EULERSPLAT_APPS_COMMON_APP_MAIN_H_

#include <functional>

namespace es {

// Runs an app body: parses gflags (with `usage` as the help text), sets up
// glog, and turns an InputError into a one-line message and exit code 1.
//
// Before the body runs:
// - --help (and -h, --helpshort) prints `usage`, then the app's own flags
//   with readable defaults, and exits 0; --helpfull adds glog's and
//   gflags' flags. --version prints the version and git commit, exits 0.
// - every floating-point flag the app defines must be finite, and every
//   learning rate (a flag named lr_*) must also be >= 0; otherwise the app
//   exits 1 naming the flag, before any work.
// - --threads (threads_flag.h) sets the OpenMP threads of the app and of
//   the processes it starts; when the user set no OpenMP wait policy, the
//   app first starts again with a short spin (wait_policy.h).
int RunApp(int argc, char** argv, const char* usage,
           const std::function<int()>& body);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_APP_MAIN_H_
