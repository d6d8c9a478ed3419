#include "solvers/pipeline/stage_process.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <utility>

#include "core/base/input_error.h"
#include "solvers/pipeline/child_process.h"

namespace es {
namespace {

namespace fs = std::filesystem;

std::string Join(const std::vector<std::string>& args) {
  std::string out;
  for (const std::string& a : args) out += (out.empty() ? "" : " ") + a;
  return out;
}

}  // namespace

std::string DeviceStageNames() {
  std::string out;
  for (const char* name : kDeviceStages) {
    out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out;
}

bool PassesDevice(const std::string& binary,
                  const std::vector<std::string>& args) {
  const std::string name = fs::path(binary).filename().string();
  if (std::find(std::begin(kDeviceStages), std::end(kDeviceStages), name) ==
      std::end(kDeviceStages))
    return false;
  return std::none_of(args.begin(), args.end(), [](const std::string& a) {
    return a == "--device" || a.rfind("--device=", 0) == 0;
  });
}

StageProcessRunner::StageProcessRunner(std::string device, fs::path binary_dir,
                                       Launch launch)
    : device_(std::move(device)),
      binary_dir_(std::move(binary_dir)),
      launch_(std::move(launch)) {}

StageProcessRunner::StageProcessRunner(std::string device)
    : StageProcessRunner(std::move(device),
                         fs::read_symlink("/proc/self/exe").parent_path(),
                         RunChildProcess) {}

int StageProcessRunner::Run(const std::string& binary,
                            std::vector<std::string> args) const {
  const std::string path = binary.find('/') == std::string::npos
                               ? (binary_dir_ / binary).string()
                               : binary;
  if (PassesDevice(binary, args)) {
    args.insert(args.end(), {"--device", device_});
  }
  std::vector<std::string> all = {path};
  all.insert(all.end(), args.begin(), args.end());
  std::printf("\n$ %s\n", Join(all).c_str());
  std::fflush(stdout);
  return launch_(path, args);
}

void StageProcessRunner::RunOrThrow(
    const std::string& stage, const std::string& binary,
    const std::vector<std::string>& args) const {
  const int status = Run(binary, args);
  if (status != 0) {
    throw InputError(stage + " failed (" + binary + " exit status " +
                     std::to_string(status) + "; its message is above)");
  }
}

}  // namespace es
