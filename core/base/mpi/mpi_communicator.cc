#include "core/base/mpi/mpi_communicator.h"

#include <glog/logging.h>

#include <algorithm>
#include <cstdlib>

#include "core/base/mpi/mpi_world.h"

namespace es {
namespace {

// MPI counts are ints: large buffers go in pieces of at most this.
constexpr size_t kMaxPiece = size_t{1} << 30;

template <typename T>
void AllreducePieces(T* data, size_t count, MPI_Datatype type, MPI_Op op,
                     MPI_Comm comm) {
  for (size_t begin = 0; begin < count; begin += kMaxPiece) {
    const int n = static_cast<int>(std::min(kMaxPiece, count - begin));
    MPI_Allreduce(MPI_IN_PLACE, data + begin, n, type, op, comm);
  }
}

}  // namespace

std::unique_ptr<MpiCommunicator> MpiCommunicator::World(int* argc,
                                                        char*** argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  CHECK(!initialized) << "one world communicator per process";
  MPI_Init(argc, argv);
  return std::unique_ptr<MpiCommunicator>(
      new MpiCommunicator(MPI_COMM_WORLD, false, true));
}

MpiCommunicator::MpiCommunicator(MPI_Comm comm, bool owns_comm,
                                 bool finalizes)
    : comm_(comm), owns_comm_(owns_comm), finalizes_(finalizes) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

MpiCommunicator::~MpiCommunicator() {
  if (owns_comm_) MPI_Comm_free(&comm_);
  if (finalizes_) MPI_Finalize();
}

void MpiCommunicator::AllreduceSum(double* data, size_t count) {
  AllreducePieces(data, count, MPI_DOUBLE, MPI_SUM, comm_);
}

void MpiCommunicator::AllreduceSum(float* data, size_t count) {
  AllreducePieces(data, count, MPI_FLOAT, MPI_SUM, comm_);
}

void MpiCommunicator::AllreduceMax(double* data, size_t count) {
  AllreducePieces(data, count, MPI_DOUBLE, MPI_MAX, comm_);
}

void MpiCommunicator::AllreduceMax(unsigned char* data, size_t count) {
  AllreducePieces(data, count, MPI_UNSIGNED_CHAR, MPI_MAX, comm_);
}

void MpiCommunicator::Broadcast(void* data, size_t bytes, int root) {
  char* bytes_data = static_cast<char*>(data);
  for (size_t begin = 0; begin < bytes; begin += kMaxPiece) {
    const int n = static_cast<int>(std::min(kMaxPiece, bytes - begin));
    MPI_Bcast(bytes_data + begin, n, MPI_BYTE, root, comm_);
  }
}

void MpiCommunicator::Barrier() { MPI_Barrier(comm_); }

std::unique_ptr<Communicator> MpiCommunicator::Split(int color) {
  MPI_Comm part;
  MPI_Comm_split(comm_, color, rank_, &part);
  return std::unique_ptr<Communicator>(new MpiCommunicator(part, true, false));
}

std::unique_ptr<Communicator> MpiWorld(int* argc, char*** argv) {
  return MpiCommunicator::World(argc, argv);
}

void MpiAbort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // not reached: MPI_Abort does not return
}

}  // namespace es
