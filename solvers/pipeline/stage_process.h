#ifndef EULERSPLAT_SOLVERS_PIPELINE_STAGE_PROCESS_H_
#define EULERSPLAT_SOLVERS_PIPELINE_STAGE_PROCESS_H_

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace es {

// The stage binaries that take --device: the driver passes its own on to
// every run of them; the other stages run on the CPU. A stage that gains a
// device path joins here. A constant array, so flag help built from it
// during static initialisation sees it filled.
inline constexpr const char* kDeviceStages[] = {
    "es_static", "es_flowinit", "es_train", "es_animate", "es_eval"};

// "es_static, es_flowinit, ..." (kDeviceStages, for messages).
std::string DeviceStageNames();

// True if `binary` takes --device (kDeviceStages) and `args` do not set it
// already (a stage that must run on the CPU says --device cpu).
bool PassesDevice(const std::string& binary,
                  const std::vector<std::string>& args);

// The stage binaries that train data-parallel over MPI ranks
// (solvers/train/data_parallel.h): with several ranks the driver starts
// them under mpiexec. Of those, the ones that take --batch_frames
// (es_flowinit shares each batch of samples, a shard per rank).
inline constexpr const char* kRankStages[] = {"es_static", "es_flowinit",
                                              "es_train"};
inline constexpr const char* kBatchFrameStages[] = {"es_static", "es_train"};

// How the driver runs kRankStages (eulersplat --ranks).
struct RankLaunch {
  int ranks = 1;            // 1: as every other stage
  int batch_frames = 1;     // passed on as --batch_frames unless given
  std::string mpiexec;      // its path
  int threads_per_rank = 0; // > 0: OMP_NUM_THREADS of each rank
};

// The path of mpiexec on PATH, or "" when there is none.
std::string FindMpiexec();

// Runs the stage binaries, each a process of its own, and prints each
// command line first ("$ ..."), so every stage can be rerun alone with the
// very same flags.
class StageProcessRunner {
 public:
  // Starts a process and returns its exit status (RunChildProcess).
  using Launch = std::function<int(const std::string& path,
                                   const std::vector<std::string>& args)>;

  // `device` goes on as --device to the stages that take it. A binary
  // named without a '/' is looked up in `binary_dir`.
  StageProcessRunner(std::string device, std::filesystem::path binary_dir,
                     Launch launch);
  // The binaries next to the running one, started by RunChildProcess.
  explicit StageProcessRunner(std::string device);

  // From now on kRankStages run on `ranks.ranks` ranks under mpiexec
  // (when above 1), kBatchFrameStages with --batch_frames (when above 1).
  void SetRanks(RankLaunch ranks) { ranks_ = std::move(ranks); }

  // Runs `binary` with `args` (plus --device where it takes it) and
  // returns its exit status.
  int Run(const std::string& binary, std::vector<std::string> args) const;

  // Run, throwing InputError naming `stage` ("[static]") and the status
  // when the binary fails.
  void RunOrThrow(const std::string& stage, const std::string& binary,
                  const std::vector<std::string>& args) const;

 private:
  std::string device_;
  std::filesystem::path binary_dir_;
  Launch launch_;
  RankLaunch ranks_;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_STAGE_PROCESS_H_
