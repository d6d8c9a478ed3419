#include "solvers/pipeline/stage_log.h"

#include <cstdio>

namespace es {

StageLog::StageLog(int total)
    : total_(total), start_(std::chrono::steady_clock::now()) {}

void StageLog::Begin(const std::string& name) {
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start_)
                             .count();
  std::printf("\n[eulersplat] stage %d/%d: %s (%.0f s so far)\n", ++done_,
              total_, name.c_str(), seconds);
  std::fflush(stdout);
}

}  // namespace es
