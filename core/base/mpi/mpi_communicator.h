#ifndef EULERSPLAT_CORE_BASE_MPI_MPI_COMMUNICATOR_H_
#define EULERSPLAT_CORE_BASE_MPI_MPI_COMMUNICATOR_H_

#include <mpi.h>

#include <memory>

#include "core/base/communicator.h"

namespace es {

// Communicator over MPI (Debian's Open MPI), built only with -DES_MPI
// (ES_HAVE_MPI). A failing MPI call aborts the job: MPI's default error
// handler, which makes mpiexec end every rank.
class MpiCommunicator : public Communicator {
 public:
  // MpiWorld (mpi_world.h).
  static std::unique_ptr<MpiCommunicator> World(int* argc, char*** argv);
  ~MpiCommunicator() override;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void AllreduceSum(double* data, size_t count) override;
  void AllreduceSum(float* data, size_t count) override;
  void AllreduceMax(double* data, size_t count) override;
  void AllreduceMax(unsigned char* data, size_t count) override;
  void Broadcast(void* data, size_t bytes, int root) override;
  void Barrier() override;
  std::unique_ptr<Communicator> Split(int color) override;

 private:
  MpiCommunicator(MPI_Comm comm, bool owns_comm, bool finalizes);

  MPI_Comm comm_;
  bool owns_comm_;  // from Split: freed with the object
  bool finalizes_;  // the world: MPI_Finalize with the object
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_MPI_MPI_COMMUNICATOR_H_
