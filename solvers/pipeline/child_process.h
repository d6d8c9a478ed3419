#ifndef EULERSPLAT_SOLVERS_PIPELINE_CHILD_PROCESS_H_
#define EULERSPLAT_SOLVERS_PIPELINE_CHILD_PROCESS_H_

#include <string>
#include <vector>

namespace es {

// Runs `path` with `args` (no shell) and waits for it. The child is sent
// SIGTERM if this process dies first (kill -9 included), so a killed driver
// never leaves a trainer running on its files. Returns the exit status, or
// 128 + the signal that ended the child; throws InputError if `path` cannot
// be run.
int RunChildProcess(const std::string& path,
                    const std::vector<std::string>& args);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_CHILD_PROCESS_H_
