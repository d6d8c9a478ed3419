#ifndef EULERSPLAT_APPS_COMMON_WORLD_H_
#define EULERSPLAT_APPS_COMMON_WORLD_H_

#include <functional>
#include <memory>
#include <string>

#include "core/base/communicator.h"

namespace es {

// The ranks a training app (es_static, es_train) trains on: every process
// mpiexec started, in a build with MPI (-DES_MPI); otherwise this process
// alone. Ranks other than 0 print nothing on stdout (progress is rank 0's);
// errors still reach stderr.
class AppWorld {
 public:
  // Throws InputError when started by mpiexec in a build without MPI.
  AppWorld();
  ~AppWorld();

  Communicator* comm() { return comm_; }

  // Runs `body`. With several ranks, an error on any of them is printed
  // with its rank and ends the whole job (mpiexec stops every rank; the
  // exit code is 1 for an InputError, 2 for another error), since the
  // others may wait for it in a collective.
  int Run(const std::function<int()>& body);

 private:
  std::unique_ptr<Communicator> owned_;
  Communicator* comm_;
};

// RunApp (app_main.h) for a training app: the body runs in an AppWorld's
// Run and gets the world's communicator.
int RunAppOnRanks(int argc, char** argv, const char* usage,
                  const std::function<int(Communicator* comm)>& body);

// Whether this build trains over MPI ranks (-DES_MPI found Open MPI).
bool BuiltWithMpi();

// The help text of --batch_frames, shared by es_static and es_train.
extern const char kBatchFramesHelp[];

// Checks --batch_frames against the ranks and the device (batches train
// on the CPU only); throws InputError naming the flag.
void CheckBatchFramesFlag(int batch_frames, const Communicator& comm,
                          bool on_cuda);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_WORLD_H_
