#include "apps/common/app_main.h"

#include <cstdio>
#include <exception>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "core/io/input_error.h"

namespace es {

int RunApp(int argc, char** argv, const char* usage,
           const std::function<int()>& body) {
  gflags::SetUsageMessage(usage);
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  FLAGS_logtostderr = true;
  google::InitGoogleLogging(argv[0]);
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}

}  // namespace es
