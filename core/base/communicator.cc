#include "core/base/communicator.h"

#include <glog/logging.h>

#include <cstdlib>

namespace es {

void SingleProcessCommunicator::Broadcast(void*, size_t, int root) {
  CHECK_EQ(root, 0) << "a single process has only rank 0";
}

std::unique_ptr<Communicator> SingleProcessCommunicator::Split(int) {
  return std::make_unique<SingleProcessCommunicator>();
}

Communicator& SingleProcess() {
  static SingleProcessCommunicator single;
  return single;
}

bool LaunchedByMpiexec() {
  // Open MPI's launcher sets the first, PMIx-based launchers the second,
  // MPICH's Hydra the third.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

}  // namespace es
