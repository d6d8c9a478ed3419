#ifndef EULERSPLAT_APPS_COMMON_APP_MAIN_H_
#define EULERSPLAT_APPS_COMMON_APP_MAIN_H_

#include <functional>

namespace es {

// Runs an app body: parses gflags (with `usage` as the help text), sets up
// glog, and turns an InputError into a one-line message and exit code 1.
int RunApp(int argc, char** argv, const char* usage,
           const std::function<int()>& body);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_APP_MAIN_H_
