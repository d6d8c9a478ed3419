#include "apps/common/world.h"

#include <cstdio>
#include <exception>

#include "apps/common/app_main.h"
#include "core/base/input_error.h"
#include "solvers/train/data_parallel.h"
#ifdef ES_HAVE_MPI
#include "core/base/mpi/mpi_world.h"
#endif

namespace es {

const char kBatchFramesHelp[] =
    "Frames per iteration: each step follows the mean gradient of this many "
    "sampled frames. Under mpiexec (eulersplat --ranks N) the ranks render "
    "a batch's frames between them (at least one each) and sum their "
    "gradients; 1 is the one-frame step. CPU only.";

bool BuiltWithMpi() {
#ifdef ES_HAVE_MPI
  return true;
#else
  return false;
#endif
}

AppWorld::AppWorld() {
  if (LaunchedByMpiexec()) {
#ifdef ES_HAVE_MPI
    owned_ = MpiWorld(nullptr, nullptr);
#else
    throw InputError(
        "started by mpiexec, but this build has no MPI: install Debian's "
        "Open MPI (libopenmpi-dev openmpi-bin) and configure with "
        "-DES_MPI=ON, or run without mpiexec");
#endif
  }
  comm_ = owned_ ? owned_.get() : &SingleProcess();
  if (comm_->rank() != 0 && std::freopen("/dev/null", "w", stdout) == nullptr)
    std::fclose(stdout);
}

AppWorld::~AppWorld() { std::fflush(stdout); }

int AppWorld::Run(const std::function<int()>& body) {
  if (comm_->size() == 1) return body();
  int code = 0;
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "error (rank %d of %d): %s\n", comm_->rank(),
                 comm_->size(), e.what());
    code = 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error (rank %d of %d): %s\n", comm_->rank(),
                 comm_->size(), e.what());
    code = 2;
  }
  std::fflush(stderr);
#ifdef ES_HAVE_MPI
  MpiAbort(code);
#endif
  return code;
}

int RunAppOnRanks(int argc, char** argv, const char* usage,
                  const std::function<int(Communicator* comm)>& body) {
  return RunApp(argc, argv, usage, [&body] {
    AppWorld world;
    return world.Run([&] { return body(world.comm()); });
  });
}

void CheckBatchFramesFlag(int batch_frames, const Communicator& comm,
                          bool on_cuda) {
  CheckBatchFrames(batch_frames, comm);
  if (on_cuda && batch_frames > 1) {
    throw InputError("--batch_frames " + std::to_string(batch_frames) +
                     ": batches train on the CPU only (--device cpu)");
  }
  if (on_cuda && comm.size() > 1)
    throw InputError("--device cuda: several ranks train on the CPU only");
}

}  // namespace es
