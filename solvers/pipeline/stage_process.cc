#include "solvers/pipeline/stage_process.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
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

template <size_t N>
bool IsOneOf(const std::string& binary, const char* const (&stages)[N]) {
  const std::string name = fs::path(binary).filename().string();
  return std::find(std::begin(stages), std::end(stages), name) !=
         std::end(stages);
}

bool HasFlag(const std::vector<std::string>& args, const std::string& flag) {
  return std::any_of(args.begin(), args.end(), [&](const std::string& a) {
    return a == flag || a.rfind(flag + "=", 0) == 0;
  });
}

}  // namespace

std::string FindMpiexec() {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "";
  size_t begin = 0;
  while (begin <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', begin), dirs.size());
    const fs::path candidate =
        fs::path(dirs.substr(begin, end - begin)) / "mpiexec";
    if (end > begin && access(candidate.c_str(), X_OK) == 0)
      return candidate.string();
    begin = end + 1;
  }
  return "";
}

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
  std::string program = path;
  if (ranks_.batch_frames > 1 && IsOneOf(binary, kBatchFrameStages) &&
      !HasFlag(args, "--batch_frames")) {
    args.insert(args.end(),
                {"--batch_frames", std::to_string(ranks_.batch_frames)});
  }
  if (ranks_.ranks > 1 && IsOneOf(binary, kRankStages)) {
    std::vector<std::string> mpi = {"-n", std::to_string(ranks_.ranks)};
    if (ranks_.threads_per_rank > 0) {
      mpi.insert(mpi.end(), {"-x", "OMP_NUM_THREADS=" +
                                       std::to_string(ranks_.threads_per_rank)});
    }
    mpi.push_back(path);
    args.insert(args.begin(), mpi.begin(), mpi.end());
    program = ranks_.mpiexec;
  }
  std::vector<std::string> all = {program};
  all.insert(all.end(), args.begin(), args.end());
  std::printf("\n$ %s\n", Join(all).c_str());
  std::fflush(stdout);
  return launch_(program, args);
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
