#include "apps/common/app_main.h"

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "apps/common/flag_help.h"
#include "apps/common/memory_policy.h"
#include "apps/common/threads_flag.h"
#include "apps/common/version.h"
#include "apps/common/wait_policy.h"
#include "core/base/input_error.h"

namespace es {
namespace {

bool FlagIsTrue(const char* name) {
  std::string value;
  return gflags::GetCommandLineOption(name, &value) && value == "true";
}

// NaN and infinity slip through gflags' parsing and would poison training
// silently; a negative learning rate climbs the loss.
void CheckFloatingPointFlags() {
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  for (const auto& flag : flags) {
    if (flag.type != "double" || !IsAppFlag(flag)) continue;
    const double value = std::strtod(flag.current_value.c_str(), nullptr);
    if (!std::isfinite(value)) {
      throw InputError("--" + flag.name + "=" + flag.current_value +
                       ": must be a finite number");
    }
    if (flag.name.rfind("lr_", 0) == 0 && value < 0) {
      throw InputError("--" + flag.name + "=" + flag.current_value +
                       ": a learning rate must be >= 0");
    }
  }
}

}  // namespace

int RunApp(int argc, char** argv, const char* usage,
           const std::function<int()>& body) {
  ApplyWaitPolicy(argv);  // may start the program again, with the policy
  KeepFreedMemory();
  gflags::SetUsageMessage(usage);
  gflags::SetVersionString(VersionString());
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "-h") == 0) {
      std::fputs(FlagHelp(usage, false).c_str(), stdout);
      return 0;
    }
  }
  gflags::ParseCommandLineNonHelpFlags(&argc, &argv, true);
  if (FlagIsTrue("help") || FlagIsTrue("helpshort") || FlagIsTrue("helpfull")) {
    std::fputs(FlagHelp(usage, FlagIsTrue("helpfull")).c_str(), stdout);
    return 0;
  }
  if (FlagIsTrue("version")) {
    std::printf("%s\n", VersionString().c_str());
    return 0;
  }
  gflags::HandleCommandLineHelpFlags();  // --helpon, --helpxml, ...: exits
  FLAGS_logtostderr = true;
  google::InitGoogleLogging(argv[0]);
  VLOG(1) << WaitPolicyDescription(std::getenv("OMP_WAIT_POLICY"),
                                   std::getenv("GOMP_SPINCOUNT"),
                                   std::getenv(kWaitPolicyMarker));
  try {
    if (argc > 1) {
      throw InputError(std::string("unexpected argument '") + argv[1] +
                       "' (flags are --name=value or --name value; see "
                       "--help)");
    }
    CheckFloatingPointFlags();
    ApplyThreadsFlag();
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
