#ifndef EULERSPLAT_CORE_BASE_COMMUNICATOR_H_
#define EULERSPLAT_CORE_BASE_COMMUNICATOR_H_

#include <cstddef>
#include <memory>

namespace es {

// The processes (ranks) that train one model together, data-parallel: each
// renders its share of a batch of frames, the gradients are summed over
// all of them, and every rank then takes the same step. The single-process
// communicator below is the default; MpiCommunicator
// (core/base/mpi/mpi_communicator.h, only in a build with -DES_MPI) spans
// the processes mpiexec started.
//
// Every call is collective: all ranks of the communicator make the same
// calls in the same order with the same sizes.
class Communicator {
 public:
  virtual ~Communicator() = default;

  virtual int rank() const = 0;
  virtual int size() const = 0;

  // data[i] <- sum over the ranks of their data[i], on every rank.
  virtual void AllreduceSum(double* data, size_t count) = 0;
  virtual void AllreduceSum(float* data, size_t count) = 0;
  // data[i] <- largest of the ranks' data[i], on every rank.
  virtual void AllreduceMax(double* data, size_t count) = 0;
  virtual void AllreduceMax(unsigned char* data, size_t count) = 0;
  // Every rank's `bytes` bytes at `data` <- those of rank `root`.
  virtual void Broadcast(void* data, size_t bytes, int root) = 0;
  virtual void Barrier() = 0;
  // The ranks that pass the same `color` as a communicator of their own
  // (ranked in the order of their ranks here): one group per scene of a
  // batch of scenes.
  virtual std::unique_ptr<Communicator> Split(int color) = 0;
};

// One process alone: rank 0 of 1; the reductions leave the data as it is.
class SingleProcessCommunicator : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void AllreduceSum(double*, size_t) override {}
  void AllreduceSum(float*, size_t) override {}
  void AllreduceMax(double*, size_t) override {}
  void AllreduceMax(unsigned char*, size_t) override {}
  void Broadcast(void*, size_t, int root) override;
  void Barrier() override {}
  std::unique_ptr<Communicator> Split(int color) override;
};

// The communicator of a caller that has none: one process.
Communicator& SingleProcess();

// Whether this process was started by mpiexec / mpirun (their
// environment): a build with MPI then joins the other ranks; a plain run
// never touches MPI.
bool LaunchedByMpiexec();

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_COMMUNICATOR_H_
