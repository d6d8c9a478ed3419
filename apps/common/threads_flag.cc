#include "apps/common/threads_flag.h"

#include <gflags/gflags.h>
#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

#include "core/base/input_error.h"

DEFINE_int32(threads, 0, "CPU threads (OpenMP) this program and the stages "
             "it starts use. 0: OMP_NUM_THREADS if set, else every core "
             "(std::thread::hardware_concurrency()). On a machine shared "
             "with other jobs, the cores left free. Idle threads spin "
             "briefly, then sleep (GOMP_SPINCOUNT=10000 unless "
             "OMP_WAIT_POLICY or GOMP_SPINCOUNT is set).");

namespace es {

int ResolvedThreads(int flag, const char* omp_num_threads) {
  if (flag < 0) {
    throw InputError("--threads=" + std::to_string(flag) +
                     ": must be >= 0 (0: every core)");
  }
  if (flag > 0) return flag;
  if (omp_num_threads != nullptr) {
    const int n = std::atoi(omp_num_threads);
    if (n > 0) return n;
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

int ApplyThreadsFlag() {
  const int threads =
      ResolvedThreads(FLAGS_threads, std::getenv("OMP_NUM_THREADS"));
  omp_set_num_threads(threads);
  ::setenv("OMP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  return threads;
}

}  // namespace es
