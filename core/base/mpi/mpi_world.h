#ifndef EULERSPLAT_CORE_BASE_MPI_MPI_WORLD_H_
#define EULERSPLAT_CORE_BASE_MPI_MPI_WORLD_H_

#include <memory>

#include "core/base/communicator.h"

namespace es {

// The MPI side the apps see, without MPI's types (so only the library
// es_mpi compiles against mpi.h). Built only with -DES_MPI.

// All processes mpiexec started (MPI_COMM_WORLD): initializes MPI, which
// is finalized when the communicator goes away. Once per process.
std::unique_ptr<Communicator> MpiWorld(int* argc, char*** argv);

// Ends every rank of the job with `code`: a rank that failed while the
// others may wait in a collective.
[[noreturn]] void MpiAbort(int code);

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_MPI_MPI_WORLD_H_
